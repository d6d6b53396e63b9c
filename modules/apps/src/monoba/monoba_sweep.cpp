// The prior-weight sweep of monocular bundle adjustment: every gauge and prior weight on the same
// scenes, averaged over seeds (see monoba.h and doc/monoba.md).
#include <swba/apps/monoba.h>
#include "../report_helpers.h"

#include <swba/core/validation.h>

#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>

namespace swba::apps
{

MonoBASweepOptions::MonoBASweepOptions()
{
	weights.push_back(0.0);
	for (int k = 0; k <= 10; k++) weights.push_back(std::pow(10.0, k));
}

void MonoBASweepOptions::validate() const
{
	if (weights.empty()) throw std::invalid_argument("no prior weights to sweep");
	for (double w : weights)
		if (!(w >= 0) || !std::isfinite(w)) throw std::invalid_argument("prior weights must be finite and ≥ 0");
	if (seeds < 1) throw std::invalid_argument("the number of seeds must be ≥ 1");
	if (repetitions < 1) throw std::invalid_argument("the number of repetitions must be ≥ 1");
}

namespace
{
using detail::print_to;
using Row = MonoBASweepRow;
/** The fields a row averages over the seeds: summed over them, then divided by their number. */
constexpr double Row::*kAveraged[] = {&Row::iterations, &Row::final_cost, &Row::solve_time_s,
									  &Row::pose_rmse_raw_m, &Row::pose_rmse_aligned_m, &Row::inverse_depth_rmse_raw,
									  &Row::camera0_drift_m, &Row::camera0_drift_deg};

/** One seed's figures in the averaged fields of a row. */
Row sample_of(const MonoBAResult& r)
{
	Row s;
	s.iterations = r.summary.iterations;
	s.final_cost = r.summary.final_cost;
	s.solve_time_s = r.solve_time_s;
	s.pose_rmse_raw_m = r.errors.pose_rmse_raw_m;
	s.pose_rmse_aligned_m = r.errors.pose_rmse_aligned_m;
	s.inverse_depth_rmse_raw = r.errors.inverse_depth_rmse_raw;
	s.camera0_drift_m = r.errors.camera0_drift_m;
	s.camera0_drift_deg = r.errors.camera0_drift_deg;
	return s;
}
}  // namespace

std::vector<MonoBASweepRow> run_prior_weight_sweep(const problems::MonoBASceneOptions& scene_options, const MonoBAOptions& options,
											 const MonoBASweepOptions& sweep)
{
	validate_with_prefix(sweep, "monoba sweep: ");
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
	std::vector<MonoBASweepRow> rows(configs.size());
	for (size_t c = 0; c < configs.size(); c++)
	{
		rows[c].gauge = to_string(configs[c].gauge);
		rows[c].weight = configs[c].weight;
	}
	for (int k = 0; k < sweep.seeds; k++)
	{
		problems::MonoBASceneOptions so = scene_options;
		so.seed = scene_options.seed + static_cast<unsigned>(k);
		const problems::MonoBAScene scene = problems::make_monoba_scene(so);
		for (size_t c = 0; c < configs.size(); c++)
		{
			MonoBAOptions o = options;
			o.gauge = configs[c].gauge;
			o.prior_weight = configs[c].weight;
			const MonoBAResult r = run_monoba(scene, o, sweep.repetitions);
			MonoBASweepRow& row = rows[c];
			const Row sample = sample_of(r);
			for (double Row::*f : kAveraged) row.*f += sample.*f;
			if (r.summary.termination != TerminationType::Convergence) row.not_converged++;
		}
	}
	const double inv = 1.0 / sweep.seeds;
	for (auto& row : rows)
		for (double Row::*f : kAveraged) row.*f *= inv;
	return rows;
}

std::string format_sweep_table(const std::vector<MonoBASweepRow>& rows, const problems::MonoBASceneOptions& so,
							   const MonoBAOptions& options, const MonoBASweepOptions& sweep)
{
	std::ostringstream os;
	print_to(os, "# swba monoba prior-weight sweep: %d cameras, %d points, noise %.6g, depth noise %.3g m, "
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
	print_to(os, "%-6s %8s %7s %13s %9s %12s %12s %12s %12s %12s %3s\n", "gauge", "W", "iters",
			 "final_cost", "time_ms", "pose_rmse_m", "pose_sim3_m", "invd_rmse", "cam0_drift_m", "cam0_drft_deg",
			 "nc");
	for (const auto& r : rows)
	{
		char w[32];
		if (r.gauge == "prior")
			std::snprintf(w, sizeof(w), "%.0e", r.weight);
		else
			std::snprintf(w, sizeof(w), "-");
		print_to(os, "%-6s %8s %7.2f %13.6e %9.3f %12.4e %12.4e %12.4e %12.4e %12.4e %3d\n",
				 r.gauge.c_str(), w, r.iterations, r.final_cost, 1e3 * r.solve_time_s, r.pose_rmse_raw_m,
				 r.pose_rmse_aligned_m, r.inverse_depth_rmse_raw, r.camera0_drift_m, r.camera0_drift_deg,
				 r.not_converged);
	}
	return os.str();
}
}  // namespace swba::apps
