// Direct (photometric) bundle adjustment: the problem, its statistics, the motion of the variables,
// the errors against ground truth and the reports (see directba.h and doc/directba.md).
#include <swba/apps/directba.h>
#include "../report_helpers.h"
#include <swba/core/manifold.h>
#include <swba/core/validation.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cstdio>
#include <sstream>
#include <stdexcept>

namespace swba::apps
{
using detail::rotation_angle_deg;

namespace
{
Eigen::Vector3d centre(const mrpt::poses::CPose3D& p) { return Eigen::Vector3d(p.x(), p.y(), p.z()); }

double median(std::vector<double> v)
{
	if (v.empty()) return 0.0;
	const size_t k = v.size() / 2;
	std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
	return v[k];
}

std::shared_ptr<const LossFunction> make_huber(double delta)
{
	if (delta <= 0) return nullptr;
	return std::make_shared<HuberLoss>(delta);
}

void check_data(const io::DirectBADataset& data)
{
	if (data.images.size() != data.world_from_camera.size())
		throw std::invalid_argument("directba: " + std::to_string(data.images.size()) + " images for " +
									std::to_string(data.world_from_camera.size()) + " poses");
	for (const auto& img : data.images)
		if (!img || img->empty()) throw std::invalid_argument("directba: empty image");
}
/** The adjustment as a swba::Problem: poses (the first fixed_cameras constant), points eliminated,
 * one whitened, robustified PhotometricPatchFactor per (point, camera). */
struct PhotometricProblem
{
	Problem problem;
	std::vector<VariableId> poses, points;
	int num_factors = 0;
};

PhotometricProblem build_photometric_problem(const io::DirectBADataset& data, const DirectBAOptions& options)
{
	PhotometricProblem pp;
	const int n = static_cast<int>(data.world_from_camera.size());
	for (int j = 0; j < n; j++)
	{
		pp.poses.push_back(pp.problem.add_pose(data.world_from_camera[j], Group::Kept));
		if (j < options.fixed_cameras) pp.problem.set_constant(pp.poses.back());
	}
	const auto r3 = euclidean_manifold(3);
	const auto loss = make_huber(options.huber_delta);
	for (size_t i = 0; i < data.points.size(); i++)
	{
		pp.points.push_back(pp.problem.add_variable(data.points[i].position.data(), r3, Group::Eliminable));
		for (int j = 0; j < n; j++)
		{
			auto f = std::make_shared<PhotometricPatchFactor>(data.points[i].patch, data.images[j], data.intrinsics,
															  options.factor);
			f->set_sigma(options.sigma);
			pp.problem.add_factor(f, {pp.poses[j], pp.points.back()}, loss);
			pp.num_factors++;
		}
	}
	return pp;
}

/** How far the adjustment moved the cameras (centres, rotation angles) and the points. */
DirectBAMotion motion(const std::vector<mrpt::poses::CPose3D>& initial_poses,
					  const std::vector<Eigen::Vector3d>& initial_points,
					  const std::vector<mrpt::poses::CPose3D>& poses, const std::vector<Eigen::Vector3d>& points)
{
	DirectBAMotion m;
	const int n = static_cast<int>(poses.size());
	double t2 = 0, r2 = 0;
	for (int j = 0; j < n; j++)
	{
		const double dt = (centre(poses[j]) - centre(initial_poses[j])).norm();
		const double dr = rotation_angle_deg(initial_poses[j], poses[j]);
		m.pose_translation_max = std::max(m.pose_translation_max, dt);
		m.pose_rotation_max_deg = std::max(m.pose_rotation_max_deg, dr);
		t2 += dt * dt;
		r2 += dr * dr;
	}
	m.pose_translation_rms = std::sqrt(t2 / n);
	m.pose_rotation_rms_deg = std::sqrt(r2 / n);
	std::vector<double> d;
	d.reserve(points.size());
	for (size_t i = 0; i < points.size(); i++) d.push_back((points[i] - initial_points[i]).norm());
	if (!d.empty())
	{
		double sum = 0;
		for (double e : d) sum += e;
		m.point_mean = sum / double(d.size());
		m.point_max = *std::max_element(d.begin(), d.end());
		m.point_median = median(d);
	}
	return m;
}
}  // namespace

void DirectBAOptions::validate() const
{
	if (!(sigma > 0) || !std::isfinite(sigma)) throw std::invalid_argument("sigma must be a positive number");
	if (!std::isfinite(huber_delta)) throw std::invalid_argument("huber delta must be finite");
	if (fixed_cameras < 0) throw std::invalid_argument("fixed_cameras must be ≥ 0");
	if (factor.border < 0) throw std::invalid_argument("border must be ≥ 0");
	solver.validate();
}

DirectBAStats direct_ba_stats(const io::DirectBADataset& data, const std::vector<mrpt::poses::CPose3D>& poses,
							  const std::vector<Eigen::Vector3d>& points, const DirectBAOptions& options)
{
	check_data(data);
	const auto loss = make_huber(options.huber_delta);
	DirectBAStats st;
	double sse = 0;
	std::vector<double> abs_res;
	std::vector<std::array<double, 12>> pose_values(poses.size());
	for (size_t j = 0; j < poses.size(); j++) SE3Manifold::from_pose(poses[j], pose_values[j].data());
	for (size_t i = 0; i < points.size(); i++)
		for (size_t j = 0; j < poses.size(); j++)
		{
			const PhotometricPatchFactor f(data.points[i].patch, data.images[j], data.intrinsics, options.factor);
			const double* x[2] = {pose_values[j].data(), points[i].data()};
			double r[kPatchSize];
			if (!f.evaluate(x, r, nullptr))
			{
				st.dropped++;
				continue;
			}
			st.evaluated++;
			double s = 0;
			for (double e : r)
			{
				s += e * e;
				abs_res.push_back(std::abs(e));
			}
			sse += s;
			const double sw = s / (options.sigma * options.sigma);
			if (loss)
			{
				double rho[3];
				loss->evaluate(sw, rho);
				st.cost += 0.5 * rho[0];
			}
			else
				st.cost += 0.5 * sw;
		}
	st.pixel_rms = st.evaluated > 0 ? std::sqrt(sse / (kPatchSize * double(st.evaluated))) : 0.0;
	st.pixel_median_abs = median(std::move(abs_res));
	return st;
}

DirectBAFixedCamerasError::DirectBAFixedCamerasError(int fixed, int cameras)
	: std::invalid_argument("fixed_cameras = " + std::to_string(fixed) + ", but the data set has " +
							std::to_string(cameras) + " cameras"),
	  fixed_cameras(fixed), num_cameras(cameras)
{
}

DirectBAResult run_direct_ba(const io::DirectBADataset& data, const DirectBAOptions& options)
{
	validate_with_prefix(options, "directba: ");
	check_data(data);
	const int n = static_cast<int>(data.world_from_camera.size());
	if (options.fixed_cameras > n) throw DirectBAFixedCamerasError(options.fixed_cameras, n);

	DirectBAResult res;
	std::vector<Eigen::Vector3d> initial_points;
	initial_points.reserve(data.points.size());
	for (const auto& p : data.points) initial_points.push_back(p.position);
	res.before = direct_ba_stats(data, data.world_from_camera, initial_points, options);

	PhotometricProblem pp = build_photometric_problem(data, options);
	res.num_factors = pp.num_factors;
	res.summary = solve(pp.problem, options.solver);

	for (int j = 0; j < n; j++) res.poses.push_back(pp.problem.pose(pp.poses[j]));
	for (auto id : pp.points)
	{
		const double* p = pp.problem.value(id);
		res.points.emplace_back(p[0], p[1], p[2]);
	}
	res.after = direct_ba_stats(data, res.poses, res.points, options);
	res.motion = motion(data.world_from_camera, initial_points, res.poses, res.points);
	return res;
}

DirectBAGroundTruthErrors direct_ba_ground_truth_errors(const io::DirectBADataset& truth,
														const std::vector<mrpt::poses::CPose3D>& poses,
														const std::vector<Eigen::Vector3d>& points)
{
	DirectBAGroundTruthErrors e;
	if (poses.size() != truth.world_from_camera.size() || points.size() != truth.points.size())
		throw std::invalid_argument("direct_ba_ground_truth_errors: sizes differ from the ground truth");
	for (size_t j = 0; j < poses.size(); j++)
	{
		e.pose_translation_max_m =
			std::max(e.pose_translation_max_m, (centre(poses[j]) - centre(truth.world_from_camera[j])).norm());
		e.pose_rotation_max_deg =
			std::max(e.pose_rotation_max_deg, rotation_angle_deg(truth.world_from_camera[j], poses[j]));
	}
	double s2 = 0;
	for (size_t i = 0; i < points.size(); i++)
	{
		const double d = (points[i] - truth.points[i].position).norm();
		s2 += d * d;
		e.point_max_m = std::max(e.point_max_m, d);
	}
	e.point_rms_m = points.empty() ? 0.0 : std::sqrt(s2 / double(points.size()));

	// Projection displacement vs ground truth over the pairs whose true projection is in the image.
	const auto& K = truth.intrinsics;
	auto project = [&](const mrpt::poses::CPose3D& T, const Eigen::Vector3d& p, Eigen::Vector2d& uv) {
		const Eigen::Matrix3d R = T.getRotationMatrix().asEigen();
		const Eigen::Vector3d pc = R.transpose() * (p - centre(T));
		if (pc.z() <= 1e-6) return false;
		uv = Eigen::Vector2d(K.fx * pc.x() / pc.z() + K.cx, K.fy * pc.y() / pc.z() + K.cy);
		return true;
	};
	double sum = 0;
	int count = 0;
	for (size_t j = 0; j < poses.size(); j++)
	{
		const auto& img = *truth.images[j];
		for (size_t i = 0; i < points.size(); i++)
		{
			Eigen::Vector2d a, b;
			if (!project(truth.world_from_camera[j], truth.points[i].position, a)) continue;
			if (a.x() < 0 || a.y() < 0 || a.x() > img.width - 1 || a.y() > img.height - 1) continue;
			if (!project(poses[j], points[i], b)) continue;
			const double d = (a - b).norm();
			sum += d;
			count++;
			e.reprojection_max_px = std::max(e.reprojection_max_px, d);
		}
	}
	e.reprojection_mean_px = count ? sum / count : 0.0;
	return e;
}

SyntheticDirectBAResult run_synthetic_direct_ba(const problems::SyntheticDirectBAOptions& scene, DirectBAOptions options)
{
	const problems::SyntheticDirectBA syn = problems::make_synthetic_directba(scene);
	options.fixed_cameras = scene.fixed_cameras;
	SyntheticDirectBAResult out;
	out.num_points = static_cast<int>(syn.truth.points.size());
	out.num_cameras = static_cast<int>(syn.truth.world_from_camera.size());
	std::vector<Eigen::Vector3d> p0;
	for (const auto& p : syn.initial.points) p0.push_back(p.position);
	out.initial_errors = direct_ba_ground_truth_errors(syn.truth, syn.initial.world_from_camera, p0);
	out.result = run_direct_ba(syn.initial, options);
	out.final_errors = direct_ba_ground_truth_errors(syn.truth, out.result.poses, out.result.points);
	return out;
}

std::string format_direct_ba_report(const DirectBAResult& r)
{
	char buf[512];
	std::ostringstream os;
	auto stats = [&](const char* name, const DirectBAStats& s) {
		std::snprintf(buf, sizeof(buf),
					  "%s cost %.6e, evaluated %d, dropped %d, per-pixel residual RMS %.3f (median |r| %.3f) gray levels\n",
					  name, s.cost, s.evaluated, s.dropped, s.pixel_rms, s.pixel_median_abs);
		os << buf;
	};
	os << "Photometric factors: " << r.num_factors << "\n";
	stats("Before:", r.before);
	stats("After: ", r.after);
	std::snprintf(buf, sizeof(buf),
				  "Pose motion: camera centres max %.6g rms %.6g; rotation max %.4f deg rms %.4f deg\n"
				  "Point motion: mean %.6g median %.6g max %.6g\n",
				  r.motion.pose_translation_max, r.motion.pose_translation_rms, r.motion.pose_rotation_max_deg,
				  r.motion.pose_rotation_rms_deg, r.motion.point_mean, r.motion.point_median, r.motion.point_max);
	os << buf;
	return os.str();
}

std::string format_direct_ba_ground_truth_errors(const DirectBAGroundTruthErrors& b, const DirectBAGroundTruthErrors& a)
{
	char buf[768];
	std::snprintf(buf, sizeof(buf),
				  "Ground truth errors (initial -> final):\n"
				  "  pose translation max  %.6f m -> %.6f m\n"
				  "  pose rotation max     %.5f deg -> %.5f deg\n"
				  "  point error rms       %.6f m -> %.6f m\n"
				  "  point error max       %.6f m -> %.6f m\n"
				  "  projection offset     mean %.3f px, max %.3f px -> mean %.4f px, max %.4f px\n",
				  b.pose_translation_max_m, a.pose_translation_max_m, b.pose_rotation_max_deg, a.pose_rotation_max_deg,
				  b.point_rms_m, a.point_rms_m, b.point_max_m, a.point_max_m, b.reprojection_mean_px,
				  b.reprojection_max_px, a.reprojection_mean_px, a.reprojection_max_px);
	return buf;
}
}  // namespace swba::apps
