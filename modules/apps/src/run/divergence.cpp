#include "divergence.h"

#include <swba/core/chi2.h>
#include <swba/core/lie.h>

#include <mrpt/poses/Lie/SE.h>

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

namespace swba::apps
{
namespace
{
/** The predicted reading (range, yaw, pitch) from `pose` with the sensor at `sensor`, of landmark `l`. */
Eigen::Vector3d predict(const mrpt::poses::CPose3D& pose, const mrpt::poses::CPose3D& sensor, const Eigen::Vector3d& l)
{
	double lx = 0, ly = 0, lz = 0;
	(pose + sensor).inverseComposePoint(l.x(), l.y(), l.z(), lx, ly, lz);
	const double range = std::sqrt(lx * lx + ly * ly + lz * lz);
	return {range, std::atan2(ly, lx), -std::asin(std::clamp(lz / range, -1.0, 1.0))};
}

/** νᵀ S⁻¹ ν for reading `z` of landmark `l` from `pose`: ν the innovation (angles wrapped), S = R +
 * J_T P_T J_Tᵀ + J_l P_l J_lᵀ with the pose's covariance P_T (tangent of MRPT's right perturbation) and
 * the landmark's P_l (their correlation left out); Jacobians by central differences. Rows (range,
 * yaw[, pitch]). */
double normalised_innovation(const mrpt::poses::CPose3D& pose, const estimators::PoseCovariance& P_T,
							 const mrpt::poses::CPose3D& sensor, const estimators::LandmarkEstimate& l,
							 const io::RangeBearingReading& z, const Eigen::Vector3d& sigma, bool planar)
{
	const int n = planar ? 2 : 3;
	const Eigen::Vector3d h = predict(pose, sensor, l.position);
	Eigen::Vector3d nu(h[0] - z.range, wrap_to_pi(h[1] - z.yaw), wrap_to_pi(h[2] - z.pitch));
	constexpr double eps = 1e-6;
	Eigen::Matrix<double, 3, 6> JT;
	for (int i = 0; i < 6; i++)
	{
		mrpt::math::CVectorFixedDouble<6> d;
		d.setZero();
		d[i] = eps;
		const auto plus = pose + mrpt::poses::Lie::SE<3>::exp(d);
		d[i] = -eps;
		const auto minus = pose + mrpt::poses::Lie::SE<3>::exp(d);
		Eigen::Vector3d diff = predict(plus, sensor, l.position) - predict(minus, sensor, l.position);
		diff[1] = wrap_to_pi(diff[1]);
		JT.col(i) = diff / (2 * eps);
	}
	Eigen::Matrix3d Jl;
	for (int i = 0; i < 3; i++)
	{
		Eigen::Vector3d dp = Eigen::Vector3d::Zero();
		dp[i] = eps;
		Eigen::Vector3d diff = predict(pose, sensor, l.position + dp) - predict(pose, sensor, l.position - dp);
		diff[1] = wrap_to_pi(diff[1]);
		Jl.col(i) = diff / (2 * eps);
	}
	Eigen::Matrix3d S = Eigen::Vector3d(sigma.cwiseAbs2()).asDiagonal();
	S += JT * P_T * JT.transpose() + Jl * l.covariance * Jl.transpose();
	const Eigen::MatrixXd Sn = S.topLeftCorner(n, n);
	const Eigen::VectorXd v = nu.head(n);
	return v.dot(Sn.ldlt().solve(v));
}
}  // namespace

std::optional<ReadingMisfit> reading_misfit(const RunRow& row, const io::Rawlog& rawlog,
											const estimators::SlidingWindowOptions& options, bool planar)
{
	if (row.landmarks.empty() || row.estimate.empty() || row.covariance.size() != row.estimate.size())
		return std::nullopt;
	std::map<double, std::size_t> pose_at;
	for (std::size_t i = 0; i < row.estimate.size(); i++) pose_at[row.estimate.stamps[i]] = i;
	std::vector<double> d2;
	for (std::size_t k = 0; k < rawlog.steps.size(); k++)
	{
		const io::RawlogStep& step = rawlog.steps[k];
		const auto p = pose_at.find(step.time());
		if (step.readings.empty() || p == pose_at.end()) continue;
		for (std::size_t i = 0; i < step.readings.size(); i++)
		{
			Eigen::Vector3d sigma;
			if (planar)
				sigma << options.sensor.resolve_range_yaw(step, &step.readings[i]), 0.0;
			else
				sigma = options.sensor.resolve(step, &step.readings[i]);
			const std::int32_t id = k < row.assigned_ids.size() && i < row.assigned_ids[k].size()
										? row.assigned_ids[k][i]
										: step.readings[i].landmark_id;
			const auto l = row.landmarks.find(id);
			if (l == row.landmarks.end()) continue;
			const double v = normalised_innovation(row.estimate.poses[p->second], row.covariance[p->second],
												   step.sensor_pose, l->second, step.readings[i], sigma, planar);
			d2.push_back(std::isfinite(v) ? v : HUGE_VAL);
		}
	}
	if (d2.empty()) return std::nullopt;
	auto mid = d2.begin() + static_cast<std::ptrdiff_t>(d2.size() / 2);
	std::nth_element(d2.begin(), mid, d2.end());
	return ReadingMisfit{*mid / chi2_quantile(0.5, planar ? 2 : 3), d2.size()};
}

void mark_diverged_rows(RunReport& report, const io::Rawlog& rawlog, const estimators::SlidingWindowOptions& options,
						bool planar)
{
	for (auto& r : report.rows)
	{
		if (r.failed) continue;
		bool finite = true;
		for (const auto& p : r.estimate.poses)
			finite = finite && std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z()) &&
					 std::isfinite(p.yaw()) && std::isfinite(p.pitch()) && std::isfinite(p.roll());
		const auto m = reading_misfit(r, rawlog, options, planar);
		if (m) r.reading_misfit = m->ratio;
		char buf[300];
		if (!finite)
			std::snprintf(buf, sizeof buf, "its estimate is not finite");
		else if (m && !(m->ratio <= kDivergedMisfit))
			std::snprintf(buf, sizeof buf,
						  "the median squared innovation of its %zu predicted readings is %.3g times what the declared "
						  "noise predicts (limit %g): the estimate diverged, or the sensor noise is declared far too small",
						  m->readings, m->ratio, kDivergedMisfit);
		else
			continue;
		r.diverged = true;
		r.divergence = buf;
		report.notes.push_back(r.label + ": DIVERGED: " + r.divergence);
	}
}
}  // namespace swba::apps
