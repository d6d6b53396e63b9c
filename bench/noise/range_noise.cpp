// swba_range_noise: how a range-bearing sensor's noise depends on the range, measured against ground
// truth, and a copy of a rawlog that declares it per reading.
//
//   swba_range_noise profile RAWLOG [--gt PATH] [--landmarks PATH] [--bin M]
//     each reading (with its landmark ID) against the range and bearing it would have from the true
//     pose to the true landmark: per range bin the count, the median error and the robust σ
//     (1.4826 × median absolute deviation), then σ_range = a + b·r fitted to the bins (least squares,
//     weighted by their counts; a = 0 where the free fit's a is negative).
//   swba_range_noise declare IN OUT --a A --b B
//     copies IN with every bearing-range observation's per-reading covariances set
//     (CObservationBearingRange::validCovariances): σ_range = A + B·r, yaw and pitch σ the
//     observation's own sensor_std_yaw / _pitch. Everything else is copied as read.
#include <swba/estimators/association_quality.h>
#include <swba/eval/ground_truth.h>
#include <swba/eval/trajectory.h>
#include <swba/io/rawlog.h>

#include "../common/rawlog_tool.h"

#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/obs/CSensoryFrame.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace
{
/** Median and robust σ (1.4826 × MAD) of `v` (not empty). */
std::pair<double, double> median_and_sigma(std::vector<double> v)
{
	const auto median = [](std::vector<double>& x) {
		std::nth_element(x.begin(), x.begin() + static_cast<std::ptrdiff_t>(x.size() / 2), x.end());
		return x[x.size() / 2];
	};
	const double m = median(v);
	for (double& x : v) x = std::abs(x - m);
	return {m, 1.4826 * median(v)};
}

/** Each reading's range and yaw errors against the true pose and landmark, by range bin. */
struct BinnedErrors
{
	std::map<long, std::vector<double>> range, yaw;
	std::size_t unknown = 0, beyond = 0;  ///< readings of a landmark not in the file / beyond the path
};

BinnedErrors binned_errors(const swba::io::Rawlog& rawlog, const std::vector<mrpt::poses::CPose3D>& poses,
						   const std::map<std::int32_t, Eigen::Vector3d>& landmarks, double bin)
{
	BinnedErrors e;
	for (std::size_t k = 0; k < rawlog.steps.size(); k++)
	{
		const auto& s = rawlog.steps[k];
		if (k + 1 >= poses.size())
		{
			e.beyond += s.readings.size();
			continue;
		}
		const mrpt::poses::CPose3D sensor = poses[k + 1] + s.sensor_pose;
		for (const auto& r : s.readings)
		{
			const auto l = landmarks.find(r.landmark_id);
			if (l == landmarks.end())
			{
				e.unknown++;
				continue;
			}
			const auto p = sensor.inverseComposePoint(mrpt::math::TPoint3D(l->second.x(), l->second.y(), l->second.z()));
			const long b = static_cast<long>(std::floor(p.norm() / bin));
			e.range[b].push_back(r.range - p.norm());
			e.yaw[b].push_back(std::remainder(r.yaw - std::atan2(p.y, p.x), 2 * M_PI));
		}
	}
	return e;
}

int profile(const std::string& path, std::string gt, std::string lm_path, double bin)
{
	if (gt.empty()) gt = swba::eval::default_ground_truth_path(path);
	if (lm_path.empty()) lm_path = swba::eval::default_landmarks_path(path);
	swba::io::RawlogReaderOptions ro;
	ro.require_landmark_ids = true;
	const swba::io::Rawlog rawlog = swba::io::read_rawlog(path, ro);
	const BinnedErrors e = binned_errors(rawlog, swba::eval::read_mrpt_ground_truth(gt).poses,
										 swba::estimators::read_landmark_ground_truth(lm_path), bin);
	std::printf("range_noise: %s: %zu readings against %s and %s", path.c_str(), rawlog.readings, gt.c_str(),
				lm_path.c_str());
	if (e.unknown || e.beyond)
		std::printf(" (%zu of a landmark not in the file, %zu beyond the path: not used)", e.unknown, e.beyond);
	std::printf("\n| range (m) | readings | range error median (m) | range σ (m) | yaw error median (rad) | yaw σ (rad) |\n"
				"|---|---|---|---|---|---|\n");
	Eigen::MatrixXd A(static_cast<Eigen::Index>(e.range.size()), 2);
	Eigen::VectorXd y(A.rows());
	Eigen::Index i = 0;
	for (const auto& [b, errs] : e.range)
	{
		const auto [rm, rs] = median_and_sigma(errs);
		const auto [ym, ys] = median_and_sigma(e.yaw.at(b));
		std::printf("| %.1f–%.1f | %zu | %+.3f | %.3f | %+.4f | %.4f |\n", b * bin, (b + 1) * bin, errs.size(), rm, rs, ym, ys);
		const double w = std::sqrt(static_cast<double>(errs.size()));
		A.row(i) << w, w * (b + 0.5) * bin;
		y[i++] = w * rs;
	}
	if (A.rows() >= 2)
	{
		Eigen::Vector2d ab = A.colPivHouseholderQr().solve(y);
		if (ab[0] < 0) ab << 0, A.col(1).dot(y) / A.col(1).squaredNorm();  // a σ is not negative at range 0
		std::printf("fit: range σ = %.4f + %.4f · r (m; bins weighted by their readings)\n", ab[0], ab[1]);
	}
	return 0;
}

int declare(const std::string& in, const std::string& out, double a, double b)
{
	if (!(a >= 0 && b >= 0 && a + b > 0)) throw std::invalid_argument("need --a >= 0, --b >= 0, not both 0");
	mrpt::obs::CRawlog rawlog;
	if (!rawlog.loadFromRawLogFile(in)) throw std::runtime_error("rawlog '" + in + "': cannot be read");
	std::size_t readings = 0;
	swba::bench::for_each_bearing_range(rawlog, [&](mrpt::obs::CObservationBearingRange& br) {
		br.validCovariances = true;
		for (auto& m : br.sensedData)
		{
			const double s = a + b * m.range;
			m.covariance.setZero();
			m.covariance(0, 0) = s * s;
			m.covariance(1, 1) = static_cast<double>(br.sensor_std_yaw) * br.sensor_std_yaw;
			m.covariance(2, 2) = static_cast<double>(br.sensor_std_pitch) * br.sensor_std_pitch;
			readings++;
		}
	});
	if (!rawlog.saveToRawLogFile(out)) throw std::runtime_error("rawlog '" + out + "': cannot be written");
	std::printf("range_noise: %zu readings declared with range σ = %g + %g · r -> %s\n", readings, a, b, out.c_str());
	return 0;
}

int run(int argc, char** argv)
{
	TCLAP::CmdLine cmd("The range dependence of a range-bearing sensor's noise against ground truth (profile), and a "
					   "copy of a rawlog declaring it per reading (declare).", ' ');
	TCLAP::UnlabeledValueArg<std::string> mode("MODE", "profile or declare", true, "", "MODE", cmd);
	TCLAP::UnlabeledValueArg<std::string> in("RAWLOG", "input rawlog", true, "", "RAWLOG", cmd);
	TCLAP::UnlabeledValueArg<std::string> out("OUT", "declare: output rawlog", false, "", "OUT", cmd);
	TCLAP::ValueArg<std::string> gt("", "gt", "profile: ground-truth robot path (Default: next to the rawlog)", false,
									"", "PATH", cmd);
	TCLAP::ValueArg<std::string> lms("", "landmarks", "profile: landmark ground truth (Default: next to the rawlog)",
									 false, "", "PATH", cmd);
	TCLAP::ValueArg<double> bin("", "bin", "profile: width of a range bin, m (Default: 1)", false, 1.0, "M", cmd);
	TCLAP::ValueArg<double> a("", "a", "declare: range σ at range 0, m (Default: 0)", false, 0.0, "A", cmd);
	TCLAP::ValueArg<double> b("", "b", "declare: range σ per metre of range (Default: 0)", false, 0.0, "B", cmd);
	cmd.parse(argc, argv);
	if (mode.getValue() == "profile")
	{
		if (!(bin.getValue() > 0)) throw std::invalid_argument("--bin must be > 0");
		return profile(in.getValue(), gt.getValue(), lms.getValue(), bin.getValue());
	}
	if (mode.getValue() == "declare")
	{
		if (out.getValue().empty()) throw std::invalid_argument("declare needs OUT");
		return declare(in.getValue(), out.getValue(), a.getValue(), b.getValue());
	}
	throw std::invalid_argument("MODE must be profile or declare, got '" + mode.getValue() + "'");
}
}  // namespace

int main(int argc, char** argv) { return swba::bench::tool_main("range_noise", argc, argv, run); }
