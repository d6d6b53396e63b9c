// Monocular inverse-depth bundle adjustment on a synthetic scene: the problem with its gauge, the
// errors against ground truth and the report (see monoba.h and doc/monoba.md).
#include <swba/apps/monoba.h>
#include "../report_helpers.h"

#include <swba/core/manifold.h>
#include <swba/core/validation.h>
#include <swba/eval/alignment.h>
#include <swba/factors/monocular_inverse_depth.h>
#include <swba/factors/pose_prior.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>

namespace swba::apps
{
using problems::MonoBAScene;

using detail::print_to;
using detail::rotation_angle_deg;

namespace
{
Eigen::Vector3d translation(const mrpt::poses::CPose3D& p) { return Eigen::Vector3d(p.x(), p.y(), p.z()); }

const char* termination_name(TerminationType t)
{
	switch (t)
	{
		case TerminationType::NotRun: return "NotRun";
		case TerminationType::Convergence: return "Convergence";
		case TerminationType::NoConvergence: return "NoConvergence";
		case TerminationType::Failure: return "Failure";
		case TerminationType::UserCost: return "UserCost";
	}
	return "?";
}

void print_scene_and_gauge(std::ostream& os, const problems::MonoBASceneOptions& so, const MonoBAOptions& options)
{
	print_to(os, "Mono BA: %d cameras on an arc of radius %.3g m, %d points, observation noise sigma = %.6g "
			 "(normalised plane), initial depth noise sigma = %.3g m, seed %u\n",
			 so.cameras, so.arc_radius_m, so.points, so.noise, so.depth_noise_m, so.seed);
	if (so.pose_noise_m > 0 || so.pose_noise_rad > 0)
	{
		print_to(os, "Initial pose noise from camera %d on: sigma %.3g m, %.3g rad\n",
				 so.pose_noise_from, so.pose_noise_m, so.pose_noise_rad);
	}
	switch (options.gauge)
	{
		case GaugeMode::Free: os << "Gauge: free (nothing fixed, 7-DoF null space damped by LM)\n"; break;
		case GaugeMode::Fixed:
			os << "Gauge: fixed (first " << options.anchors << " pose" << (options.anchors > 1 ? "s" : "")
			   << " constant)\n";
			break;
		case GaugeMode::Prior:
			print_to(os, "Gauge: prior (pose prior with information %.6g * I on the first %d pose%s)\n",
					 options.prior_weight, options.anchors, options.anchors > 1 ? "s" : "");
			break;
	}
}

/** The solver's full report, or (without times, for deterministic output) its figures only. */
void print_solver_summary(std::ostream& os, const Summary& summary, bool with_times)
{
	if (with_times)
	{
		os << summary.full_report();
		return;
	}
	print_to(os, "\nInitial cost: %.12e\nFinal cost: %.12e\nIterations: %d\nTermination: %s (%s)\n",
			 summary.initial_cost, summary.final_cost, summary.iterations, termination_name(summary.termination),
			 summary.message.c_str());
}

void print_camera_table(std::ostream& os, const MonoBAScene& scene, const MonoBAResult& result)
{
	os << "\nCamera translations (world frame, m), optimised vs ground truth:\n";
	print_to(os, "%-6s %-36s %-36s %10s %10s\n", "camera", "optimised", "ground truth",
			 "|error| m", "rot. deg");
	for (size_t n = 0; n < result.poses.size(); n++)
	{
		const auto& p = result.poses[n];
		const auto& g = scene.true_poses[n];
		char a[64], b[64];
		std::snprintf(a, sizeof(a), "(%10.6f, %10.6f, %10.6f)", p.x(), p.y(), p.z());
		std::snprintf(b, sizeof(b), "(%10.6f, %10.6f, %10.6f)", g.x(), g.y(), g.z());
		print_to(os, "%-6zu %-36s %-36s %10.6f %10.6f\n", n, a, b,
				 (translation(p) - translation(g)).norm(), rotation_angle_deg(g, p));
	}
}

void print_inverse_depth_table(std::ostream& os, const MonoBAScene& scene, const MonoBAResult& result)
{
	os << "\nPoint inverse depths (1/m, in the host camera):\n";
	print_to(os, "%-5s %-4s %14s %14s %14s %12s\n", "point", "host", "ground truth",
			 "noisy (init.)", "optimised", "rel. error");
	for (size_t i = 0; i < scene.points.size(); i++)
	{
		const auto& pt = scene.points[i];
		const double l = result.inverse_depths[i];
		print_to(os, "%-5zu %-4d %14.8f %14.8f %14.8f %11.4f%%\n", i, pt.host,
				 pt.true_inverse_depth, pt.initial_inverse_depth, l,
				 100.0 * (l - pt.true_inverse_depth) / pt.true_inverse_depth);
	}
}

void print_errors(std::ostream& os, const MonoBAErrors& e)
{
	os << "\nErrors vs ground truth (raw = in the solution's frame; aligned = after Sim(3) alignment of the "
		  "camera centres):\n";
	print_to(os, "  camera centres RMSE: raw %.6e m, aligned %.6e m (alignment scale %.9f)\n"
			 "  rotation RMSE (raw): %.6e deg\n"
			 "  inverse depth RMSE: raw %.6e 1/m, aligned %.6e 1/m; max relative error (raw) %.4f %%\n"
			 "  camera 0 drift (raw): %.6e m, %.6e deg\n",
			 e.pose_rmse_raw_m, e.pose_rmse_aligned_m, e.alignment_scale, e.rotation_rmse_raw_deg,
			 e.inverse_depth_rmse_raw, e.inverse_depth_rmse_aligned, 100.0 * e.inverse_depth_max_rel_raw,
			 e.camera0_drift_m, e.camera0_drift_deg);
}
}  // namespace

void MonoBAOptions::validate() const
{
	if (gauge != GaugeMode::Free && anchors < 1)
		throw std::invalid_argument("the number of anchor poses (--fix) must be ≥ 1 with the " + to_string(gauge) +
									" gauge");
	if (!(prior_weight >= 0) || !std::isfinite(prior_weight))
		throw std::invalid_argument("the prior weight must be a finite number ≥ 0");
	solver.validate();
}

MonoBAProblem build_monoba_problem(const MonoBAScene& scene, const MonoBAOptions& options)
{
	validate_with_prefix(options, "monoba: ");
	const int N = static_cast<int>(scene.initial_poses.size());
	if (options.gauge != GaugeMode::Free && options.anchors > N)
		throw std::invalid_argument("monoba: " + std::to_string(options.anchors) + " anchor poses requested but the scene has " +
									std::to_string(N) + " cameras");
	MonoBAProblem mp;
	for (int n = 0; n < N; n++) mp.poses.push_back(mp.problem.add_pose(scene.initial_poses[n]));
	if (options.gauge == GaugeMode::Fixed)
		for (int n = 0; n < options.anchors; n++) mp.problem.set_constant(mp.poses[n]);
	if (options.gauge == GaugeMode::Prior && options.prior_weight > 0)
		for (int n = 0; n < options.anchors; n++)
		{
			auto prior = std::make_shared<PosePriorFactor>(scene.initial_poses[n]);
			prior->set_information(options.prior_weight * Eigen::Matrix<double, 6, 6>::Identity());
			mp.prior_factors.push_back(mp.problem.add_factor(prior, {mp.poses[n]}));
		}
	const double sigma = scene.options.noise > 0 ? scene.options.noise : 1.0 / 460.0;
	const auto line = euclidean_manifold(1);
	for (const auto& pt : scene.points)
	{
		const VariableId lambda = mp.problem.add_variable(&pt.initial_inverse_depth, line, Group::Eliminable);
		mp.inverse_depths.push_back(lambda);
		for (const auto& ob : pt.observations)
		{
			auto f = std::make_shared<MonocularInverseDepthFactor>(pt.host_bearing, ob.uv);
			f->set_sigma(sigma);
			mp.problem.add_factor(f, {mp.poses[pt.host], mp.poses[ob.camera], lambda});
		}
	}
	return mp;
}

MonoBAErrors monoba_errors(const MonoBAScene& scene, const std::vector<mrpt::poses::CPose3D>& poses,
						   const std::vector<double>& inverse_depths)
{
	const size_t N = scene.true_poses.size(), M = scene.points.size();
	if (poses.size() != N || inverse_depths.size() != M)
		throw std::invalid_argument("monoba_errors: solution does not match the scene");
	MonoBAErrors e;
	Eigen::Matrix3Xd est(3, N), gt(3, N);
	double sse_t = 0, sse_r = 0;
	for (size_t n = 0; n < N; n++)
	{
		est.col(n) = translation(poses[n]);
		gt.col(n) = translation(scene.true_poses[n]);
		sse_t += (est.col(n) - gt.col(n)).squaredNorm();
		const double a = rotation_angle_deg(scene.true_poses[n], poses[n]);
		sse_r += a * a;
	}
	e.pose_rmse_raw_m = std::sqrt(sse_t / N);
	e.rotation_rmse_raw_deg = std::sqrt(sse_r / N);
	e.camera0_drift_m = (est.col(0) - gt.col(0)).norm();
	e.camera0_drift_deg = rotation_angle_deg(scene.true_poses[0], poses[0]);
	const eval::Sim3 S = eval::umeyama_alignment(est, gt, true);
	e.alignment_scale = S.scale;
	double sse_a = 0;
	for (size_t n = 0; n < N; n++) sse_a += (S.scale * S.R * est.col(n) + S.t - gt.col(n)).squaredNorm();
	e.pose_rmse_aligned_m = std::sqrt(sse_a / N);
	double sse_l = 0, sse_la = 0;
	for (size_t i = 0; i < M; i++)
	{
		const double gt_l = scene.points[i].true_inverse_depth;
		const double d = inverse_depths[i] - gt_l;
		sse_l += d * d;
		const double da = inverse_depths[i] / S.scale - gt_l;
		sse_la += da * da;
		e.inverse_depth_max_rel_raw = std::max(e.inverse_depth_max_rel_raw, std::abs(d) / gt_l);
	}
	e.inverse_depth_rmse_raw = std::sqrt(sse_l / M);
	e.inverse_depth_rmse_aligned = std::sqrt(sse_la / M);
	return e;
}

MonoBAResult run_monoba(const MonoBAScene& scene, const MonoBAOptions& options, int repetitions)
{
	if (repetitions < 1) throw std::invalid_argument("monoba: repetitions must be ≥ 1");
	MonoBAResult res;
	std::vector<double> times;
	for (int rep = 0; rep < repetitions; rep++)
	{
		MonoBAProblem mp = build_monoba_problem(scene, options);
		const Summary s = solve(mp.problem, options.solver);
		times.push_back(s.time_total_s);
		if (rep > 0) continue;
		res.summary = s;
		for (VariableId id : mp.poses) res.poses.push_back(mp.problem.pose(id));
		for (VariableId id : mp.inverse_depths) res.inverse_depths.push_back(mp.problem.value(id)[0]);
	}
	std::sort(times.begin(), times.end());
	const size_t k = times.size();
	res.solve_time_s = k % 2 ? times[k / 2] : 0.5 * (times[k / 2 - 1] + times[k / 2]);
	res.errors = monoba_errors(scene, res.poses, res.inverse_depths);
	return res;
}

std::string format_monoba_report(const MonoBAScene& scene, const MonoBAOptions& options,
								 const MonoBAResult& result, bool with_times)
{
	std::ostringstream os;
	print_scene_and_gauge(os, scene.options, options);
	int num_factors = 0;
	for (const auto& p : scene.points) num_factors += static_cast<int>(p.observations.size());
	os << "Reprojection factors: " << num_factors << "\n";
	print_solver_summary(os, result.summary, with_times);
	print_camera_table(os, scene, result);
	print_inverse_depth_table(os, scene, result);
	print_errors(os, result.errors);
	return os.str();
}
}  // namespace swba::apps
