// Monocular inverse-depth bundle adjustment on a synthetic scene, gauge modes and the prior-weight
// sweep (see monoba.h and doc/monoba.md).
#include <swba/estimators/monoba.h>

#include <swba/core/manifold.h>
#include <swba/eval/alignment.h>
#include <swba/factors/monocular_inverse_depth.h>
#include <swba/factors/pose_prior.h>

#include <mrpt/poses/Lie/SE.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <sstream>
#include <stdexcept>

namespace swba::estimators
{
namespace
{
bool fail(std::string* why, const std::string& msg)
{
	if (why) *why = msg;
	return false;
}

/** Rotation angle of R_aᵀ R_b in degrees. */
double rotation_angle_deg(const mrpt::poses::CPose3D& a, const mrpt::poses::CPose3D& b)
{
	const Eigen::Matrix3d E = a.getRotationMatrix().asEigen().transpose() * b.getRotationMatrix().asEigen();
	const double c = std::clamp((E.trace() - 1.0) / 2.0, -1.0, 1.0);
	return std::acos(c) * 180.0 / M_PI;
}

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
}  // namespace

bool MonoBASceneOptions::is_valid(std::string* why) const
{
	if (cameras < 2) return fail(why, "the number of cameras must be ≥ 2 (got " + std::to_string(cameras) + ")");
	if (points < 1) return fail(why, "the number of points must be ≥ 1 (got " + std::to_string(points) + ")");
	if (!(arc_radius_m > 0) || !std::isfinite(arc_radius_m)) return fail(why, "the arc radius must be > 0");
	if (!(noise >= 0) || !std::isfinite(noise)) return fail(why, "the observation noise must be a number ≥ 0");
	if (!(depth_noise_m >= 0) || !std::isfinite(depth_noise_m))
		return fail(why, "the depth noise must be a number ≥ 0");
	if (!(pose_noise_m >= 0) || !std::isfinite(pose_noise_m) || !(pose_noise_rad >= 0) ||
		!std::isfinite(pose_noise_rad))
		return fail(why, "the pose noise must be a number ≥ 0");
	if (pose_noise_from < 0) return fail(why, "pose_noise_from must be ≥ 0");
	return true;
}

MonoBAScene make_monoba_scene(const MonoBASceneOptions& o)
{
	if (std::string why; !o.is_valid(&why)) throw std::invalid_argument("monoba scene: " + why);
	MonoBAScene scene;
	scene.options = o;
	const int N = o.cameras;
	for (int n = 0; n < N; n++)
	{
		// A quarter circle (as seed 000: θ_n = n·2π/(4N)), all cameras looking along world +z.
		const double theta = n * (M_PI / 2.0) / N;
		const double r = o.arc_radius_m;
		scene.true_poses.emplace_back(r * std::cos(theta) - r, r * std::sin(theta), std::sin(2.0 * theta), theta,
									  0.0, 0.0);
	}

	// Points, observations and initial depths from one stream; pose noise from a second one, so that
	// enabling pose noise does not change the points.
	std::seed_seq seq_points{o.seed, 1u}, seq_poses{o.seed, 2u};
	std::mt19937 rng(seq_points), rng_pose(seq_poses);
	std::normal_distribution<double> gauss(0.0, 1.0);
	std::uniform_real_distribution<double> uxy(-4.0, 4.0), uz(4.0, 8.0);

	std::vector<Eigen::Matrix3d> Rwc;
	std::vector<Eigen::Vector3d> twc;
	for (const auto& p : scene.true_poses)
	{
		Rwc.push_back(p.getRotationMatrix().asEigen());
		twc.push_back(translation(p));
	}
	for (int i = 0; i < o.points; i++)
	{
		for (int attempt = 0;; attempt++)
		{
			if (attempt == 1000) throw std::runtime_error("monoba scene: cannot place a point seen by two cameras");
			MonoBAPoint pt;
			pt.world.x() = uxy(rng);
			pt.world.y() = uxy(rng);
			pt.world.z() = uz(rng);
			std::vector<int> seen;
			std::vector<Eigen::Vector3d> in_cam;
			for (int n = 0; n < N; n++)
			{
				const Eigen::Vector3d pc = Rwc[n].transpose() * (pt.world - twc[n]);
				if (pc.z() > 0.1)
				{
					seen.push_back(n);
					in_cam.push_back(pc);
				}
			}
			if (seen.size() < 2) continue;
			for (size_t k = 0; k < seen.size(); k++)
			{
				Eigen::Vector2d uv(in_cam[k].x() / in_cam[k].z(), in_cam[k].y() / in_cam[k].z());
				uv.x() += o.noise * gauss(rng);
				uv.y() += o.noise * gauss(rng);
				if (k == 0)
				{
					pt.host = seen[0];
					pt.host_bearing = uv;
				}
				else
					pt.observations.push_back({seen[k], uv});
			}
			const double z = in_cam[0].z();
			pt.true_inverse_depth = 1.0 / z;
			double z0 = z;
			if (o.depth_noise_m > 0)
				do
					z0 = z + o.depth_noise_m * gauss(rng);
				while (z0 < 0.5);
			pt.initial_inverse_depth = 1.0 / z0;
			scene.points.push_back(std::move(pt));
			break;
		}
	}

	scene.initial_poses = scene.true_poses;
	if (o.pose_noise_m > 0 || o.pose_noise_rad > 0)
	{
		const auto se3 = SE3Manifold::instance();
		for (int n = o.pose_noise_from; n < N; n++)
		{
			double x[12], delta[6];
			SE3Manifold::from_pose(scene.true_poses[n], x);
			for (int k = 0; k < 3; k++) delta[k] = o.pose_noise_m * gauss(rng_pose);
			for (int k = 3; k < 6; k++) delta[k] = o.pose_noise_rad * gauss(rng_pose);
			se3->plus(x, delta, x);
			scene.initial_poses[n] = SE3Manifold::to_pose(x);
		}
	}
	return scene;
}

bool MonoBAOptions::is_valid(std::string* why) const
{
	if (gauge != GaugeMode::Free && anchors < 1)
		return fail(why, "the number of anchor poses (--fix) must be ≥ 1 with the " + to_string(gauge) + " gauge");
	if (!(prior_weight >= 0) || !std::isfinite(prior_weight))
		return fail(why, "the prior weight must be a finite number ≥ 0");
	return solver.is_valid(why);
}

MonoBAProblem build_monoba_problem(const MonoBAScene& scene, const MonoBAOptions& options)
{
	if (std::string why; !options.is_valid(&why)) throw std::invalid_argument("monoba: " + why);
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
	char buf[512];
	const auto& so = scene.options;
	std::snprintf(buf, sizeof(buf),
				  "Mono BA: %d cameras on an arc of radius %.3g m, %d points, observation noise sigma = %.6g "
				  "(normalised plane), initial depth noise sigma = %.3g m, seed %u\n",
				  so.cameras, so.arc_radius_m, so.points, so.noise, so.depth_noise_m, so.seed);
	os << buf;
	if (so.pose_noise_m > 0 || so.pose_noise_rad > 0)
	{
		std::snprintf(buf, sizeof(buf), "Initial pose noise from camera %d on: sigma %.3g m, %.3g rad\n",
					  so.pose_noise_from, so.pose_noise_m, so.pose_noise_rad);
		os << buf;
	}
	switch (options.gauge)
	{
		case GaugeMode::Free: os << "Gauge: free (nothing fixed, 7-DoF null space damped by LM)\n"; break;
		case GaugeMode::Fixed:
			os << "Gauge: fixed (first " << options.anchors << " pose" << (options.anchors > 1 ? "s" : "")
			   << " constant)\n";
			break;
		case GaugeMode::Prior:
			std::snprintf(buf, sizeof(buf), "Gauge: prior (pose prior with information %.6g * I on the first %d pose%s)\n",
						  options.prior_weight, options.anchors, options.anchors > 1 ? "s" : "");
			os << buf;
			break;
	}
	int num_factors = 0;
	for (const auto& p : scene.points) num_factors += static_cast<int>(p.observations.size());
	os << "Reprojection factors: " << num_factors << "\n";
	if (with_times)
		os << result.summary.full_report();
	else
	{
		std::snprintf(buf, sizeof(buf), "\nInitial cost: %.12e\nFinal cost: %.12e\nIterations: %d\nTermination: %s (%s)\n",
					  result.summary.initial_cost, result.summary.final_cost, result.summary.iterations,
					  termination_name(result.summary.termination),
					  result.summary.message.c_str());
		os << buf;
	}

	os << "\nCamera translations (world frame, m), optimised vs ground truth:\n";
	std::snprintf(buf, sizeof(buf), "%-6s %-36s %-36s %10s %10s\n", "camera", "optimised", "ground truth",
				  "|error| m", "rot. deg");
	os << buf;
	for (size_t n = 0; n < result.poses.size(); n++)
	{
		const auto& p = result.poses[n];
		const auto& g = scene.true_poses[n];
		char a[64], b[64];
		std::snprintf(a, sizeof(a), "(%10.6f, %10.6f, %10.6f)", p.x(), p.y(), p.z());
		std::snprintf(b, sizeof(b), "(%10.6f, %10.6f, %10.6f)", g.x(), g.y(), g.z());
		std::snprintf(buf, sizeof(buf), "%-6zu %-36s %-36s %10.6f %10.6f\n", n, a, b,
					  (translation(p) - translation(g)).norm(), rotation_angle_deg(g, p));
		os << buf;
	}
	os << "\nPoint inverse depths (1/m, in the host camera):\n";
	std::snprintf(buf, sizeof(buf), "%-5s %-4s %14s %14s %14s %12s\n", "point", "host", "ground truth",
				  "noisy (init.)", "optimised", "rel. error");
	os << buf;
	for (size_t i = 0; i < scene.points.size(); i++)
	{
		const auto& pt = scene.points[i];
		const double l = result.inverse_depths[i];
		std::snprintf(buf, sizeof(buf), "%-5zu %-4d %14.8f %14.8f %14.8f %11.4f%%\n", i, pt.host,
					  pt.true_inverse_depth, pt.initial_inverse_depth, l,
					  100.0 * (l - pt.true_inverse_depth) / pt.true_inverse_depth);
		os << buf;
	}
	const auto& e = result.errors;
	os << "\nErrors vs ground truth (raw = in the solution's frame; aligned = after Sim(3) alignment of the "
		  "camera centres):\n";
	std::snprintf(buf, sizeof(buf),
				  "  camera centres RMSE: raw %.6e m, aligned %.6e m (alignment scale %.9f)\n"
				  "  rotation RMSE (raw): %.6e deg\n"
				  "  inverse depth RMSE: raw %.6e 1/m, aligned %.6e 1/m; max relative error (raw) %.4f %%\n"
				  "  camera 0 drift (raw): %.6e m, %.6e deg\n",
				  e.pose_rmse_raw_m, e.pose_rmse_aligned_m, e.alignment_scale, e.rotation_rmse_raw_deg,
				  e.inverse_depth_rmse_raw, e.inverse_depth_rmse_aligned, 100.0 * e.inverse_depth_max_rel_raw,
				  e.camera0_drift_m, e.camera0_drift_deg);
	os << buf;
	return os.str();
}

SweepOptions::SweepOptions()
{
	weights.push_back(0.0);
	for (int k = 0; k <= 10; k++) weights.push_back(std::pow(10.0, k));
}

bool SweepOptions::is_valid(std::string* why) const
{
	if (weights.empty()) return fail(why, "no prior weights to sweep");
	for (double w : weights)
		if (!(w >= 0) || !std::isfinite(w)) return fail(why, "prior weights must be finite and ≥ 0");
	if (seeds < 1) return fail(why, "the number of seeds must be ≥ 1");
	if (repetitions < 1) return fail(why, "the number of repetitions must be ≥ 1");
	return true;
}

std::vector<SweepRow> run_prior_weight_sweep(const MonoBASceneOptions& scene_options, const MonoBAOptions& options,
											 const SweepOptions& sweep)
{
	if (std::string why; !sweep.is_valid(&why)) throw std::invalid_argument("monoba sweep: " + why);
	struct Config
	{
		GaugeMode gauge;
		double weight;
	};
	std::vector<Config> configs;
	if (sweep.reference_rows)
	{
		configs.push_back({GaugeMode::Free, 0.0});
		configs.push_back({GaugeMode::Fixed, 0.0});
	}
	for (double w : sweep.weights) configs.push_back({GaugeMode::Prior, w});
	std::vector<SweepRow> rows(configs.size());
	for (size_t c = 0; c < configs.size(); c++)
	{
		rows[c].gauge = to_string(configs[c].gauge);
		rows[c].weight = configs[c].weight;
	}
	for (int k = 0; k < sweep.seeds; k++)
	{
		MonoBASceneOptions so = scene_options;
		so.seed = scene_options.seed + static_cast<unsigned>(k);
		const MonoBAScene scene = make_monoba_scene(so);
		for (size_t c = 0; c < configs.size(); c++)
		{
			MonoBAOptions o = options;
			o.gauge = configs[c].gauge;
			o.prior_weight = configs[c].weight;
			const MonoBAResult r = run_monoba(scene, o, sweep.repetitions);
			SweepRow& row = rows[c];
			row.iterations += r.summary.iterations;
			row.final_cost += r.summary.final_cost;
			row.solve_time_s += r.solve_time_s;
			row.pose_rmse_raw_m += r.errors.pose_rmse_raw_m;
			row.pose_rmse_aligned_m += r.errors.pose_rmse_aligned_m;
			row.inverse_depth_rmse_raw += r.errors.inverse_depth_rmse_raw;
			row.camera0_drift_m += r.errors.camera0_drift_m;
			row.camera0_drift_deg += r.errors.camera0_drift_deg;
			if (r.summary.termination != TerminationType::Convergence) row.not_converged++;
		}
	}
	const double inv = 1.0 / sweep.seeds;
	for (auto& row : rows)
	{
		row.iterations *= inv;
		row.final_cost *= inv;
		row.solve_time_s *= inv;
		row.pose_rmse_raw_m *= inv;
		row.pose_rmse_aligned_m *= inv;
		row.inverse_depth_rmse_raw *= inv;
		row.camera0_drift_m *= inv;
		row.camera0_drift_deg *= inv;
	}
	return rows;
}

std::string format_sweep_table(const std::vector<SweepRow>& rows, const MonoBASceneOptions& so,
							   const MonoBAOptions& options, const SweepOptions& sweep)
{
	std::ostringstream os;
	char buf[512];
	std::snprintf(buf, sizeof(buf),
				  "# swba monoba prior-weight sweep: %d cameras, %d points, noise %.6g, depth noise %.3g m, "
				  "pose noise %.3g m / %.3g rad (cameras >= %d)\n"
				  "# K = %d anchor poses (fixed: constant; prior: information W*I at the initial value; W = 0: no prior)\n"
				  "# means over %d seed(s) %u..%u; time = mean over seeds of the median of %d solve(s); "
				  "max %d iterations, %d thread(s)\n"
				  "# pose RMSE raw = camera centres in the solution frame; sim3 = after Sim(3) alignment; "
				  "drift = camera 0 raw; nc = seeds not converged\n",
				  so.cameras, so.points, so.noise, so.depth_noise_m, so.pose_noise_m, so.pose_noise_rad,
				  so.pose_noise_from, options.anchors, sweep.seeds, so.seed,
				  so.seed + static_cast<unsigned>(sweep.seeds) - 1, sweep.repetitions, options.solver.max_iterations,
				  options.solver.num_threads);
	os << buf;
	std::snprintf(buf, sizeof(buf), "%-6s %8s %7s %13s %9s %12s %12s %12s %12s %12s %3s\n", "gauge", "W", "iters",
				  "final_cost", "time_ms", "pose_rmse_m", "pose_sim3_m", "invd_rmse", "cam0_drift_m", "cam0_drft_deg",
				  "nc");
	os << buf;
	for (const auto& r : rows)
	{
		char w[32];
		if (r.gauge == "prior")
			std::snprintf(w, sizeof(w), "%.0e", r.weight);
		else
			std::snprintf(w, sizeof(w), "-");
		std::snprintf(buf, sizeof(buf), "%-6s %8s %7.2f %13.6e %9.3f %12.4e %12.4e %12.4e %12.4e %12.4e %3d\n",
					  r.gauge.c_str(), w, r.iterations, r.final_cost, 1e3 * r.solve_time_s, r.pose_rmse_raw_m,
					  r.pose_rmse_aligned_m, r.inverse_depth_rmse_raw, r.camera0_drift_m, r.camera0_drift_deg,
					  r.not_converged);
		os << buf;
	}
	return os.str();
}
}  // namespace swba::estimators
