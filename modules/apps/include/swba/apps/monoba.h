/** \file monoba.h
 * `swba monoba`: monocular bundle adjustment on a synthetic scene (swba/problems/monoba.h) and the
 * gauge study: free / fixed / prior gauge, and the prior-weight sweep after Zhang, Gallego &
 * Scaramuzza 2018. The host observation of each point defines its bearing; the other observations
 * become MonocularInverseDepthFactor's whitened by 1/σ. See doc/monoba.md. */
#pragma once

#include <swba/nonlinear/gauge.h>  // GaugeMode, shared with the sliding window
#include <swba/nonlinear/problem.h>
#include <swba/nonlinear/solver.h>
#include <swba/problems/monoba.h>

#include <mrpt/poses/CPose3D.h>

#include <iosfwd>
#include <string>
#include <vector>

namespace swba::apps
{
struct MonoBAOptions
{
	/** Gauge handling. Default Fixed. */
	GaugeMode gauge = GaugeMode::Fixed;
	/** K: the first K poses are constant (Fixed) or under the prior (Prior); ignored by Free. 1 ≤ K ≤ N.
	 * Default 2 (fixing two poses removes the whole 7-DoF gauge, scale included). */
	int anchors = 2;
	/** W ≥ 0: prior information W·I (6×6, order [ρ, ω] in m and rad) on each anchor pose at its initial
	 * value. W = 0 adds no prior factor (then identical to Free). Default 1e4. */
	double prior_weight = 1e4;
	/** LM options. Default SolverOptions' (50 iterations, 1 thread). */
	SolverOptions solver;

	/** Throws std::invalid_argument naming the option that is out of range. */
	void validate() const;
};

/** The problem built from a scene, with the ids of its variables. */
struct MonoBAProblem
{
	Problem problem;
	std::vector<VariableId> poses;           ///< per camera
	std::vector<VariableId> inverse_depths;  ///< per point
	std::vector<FactorId> prior_factors;     ///< gauge priors (Prior mode)
};

/** Builds the problem at the scene's initial values. Throws std::invalid_argument when the options
 * are invalid or K exceeds the number of cameras. */
MonoBAProblem build_monoba_problem(const problems::MonoBAScene& scene, const MonoBAOptions& options);

/** Errors of a solution against the ground truth of its scene.
 * "raw": in the problem's own frame (meaningful for Fixed/Prior, which anchor the gauge at the
 * ground-truth-valued first poses). "aligned": after the Sim(3) (Umeyama) alignment of the camera
 * centres onto the ground truth; inverse depths are then divided by the alignment scale. */
struct MonoBAErrors
{
	double pose_rmse_raw_m = 0;         ///< RMSE of camera centres, raw
	double rotation_rmse_raw_deg = 0;   ///< RMS rotation angle of R_gtᵀR, raw
	double pose_rmse_aligned_m = 0;     ///< RMSE of camera centres after Sim(3) alignment
	double alignment_scale = 1;         ///< s of x_gt ≈ s·R·x + t
	double inverse_depth_rmse_raw = 0;  ///< 1/m
	double inverse_depth_rmse_aligned = 0;
	double inverse_depth_max_rel_raw = 0;  ///< max_i |λ_i − λ_i,gt| / λ_i,gt
	double camera0_drift_m = 0;         ///< ‖t₀ − t₀,gt‖, raw
	double camera0_drift_deg = 0;       ///< rotation angle of R₀,gtᵀR₀, raw
};

MonoBAErrors monoba_errors(const problems::MonoBAScene& scene, const std::vector<mrpt::poses::CPose3D>& poses,
						   const std::vector<double>& inverse_depths);

struct MonoBAResult
{
	Summary summary;
	std::vector<mrpt::poses::CPose3D> poses;  ///< optimised T_wc
	std::vector<double> inverse_depths;       ///< optimised, per point
	MonoBAErrors errors;
	double solve_time_s = 0;  ///< median of `repetitions` solve() wall times (Summary::time_total_s)
};

/** Builds, solves and evaluates. `repetitions` ≥ 1 solves from the same initial values (the solver is
 * deterministic: the results are those of the first solve) to take the median time. */
MonoBAResult run_monoba(const problems::MonoBAScene& scene, const MonoBAOptions& options, int repetitions = 1);

/** The text report: options, solver summary, per-camera translations vs ground truth, per-point
 * inverse depth (ground truth / noisy initial / optimised) and the error summary. Deterministic
 * except for the times printed by the solver summary when `with_times`. */
std::string format_monoba_report(const problems::MonoBAScene& scene, const MonoBAOptions& options,
								 const MonoBAResult& result, bool with_times = true);

/** The prior-weight sweep. */
struct MonoBASweepOptions
{
	/** Prior weights W; default 0, 1, 10, …, 1e10. */
	std::vector<double> weights;
	/** Seeds scene.seed, …, scene.seed + seeds − 1 are averaged. Default 1. */
	int seeds = 1;
	/** Solves per (seed, W) for the median time. Default 1. */
	int repetitions = 1;
	/** Also add reference rows for the Free and Fixed gauges. Default true. */
	bool reference_rows = true;

	MonoBASweepOptions();
	/** Throws std::invalid_argument naming the option that is out of range. */
	void validate() const;
};

/** One row of the sweep table: means over the seeds. */
struct MonoBASweepRow
{
	std::string gauge;  ///< "prior", "free", "fixed"
	double weight = 0;  ///< W (prior rows)
	double iterations = 0;
	double final_cost = 0;
	double solve_time_s = 0;
	double pose_rmse_raw_m = 0;
	double pose_rmse_aligned_m = 0;
	double inverse_depth_rmse_raw = 0;
	double camera0_drift_m = 0;
	double camera0_drift_deg = 0;
	int not_converged = 0;  ///< seeds whose solve ended with NoConvergence or Failure
};

/** Runs the sweep: every gauge/weight on the same scenes (options.gauge is ignored; options.anchors
 * is the K of the prior and fixed rows). */
std::vector<MonoBASweepRow> run_prior_weight_sweep(const problems::MonoBASceneOptions& scene, const MonoBAOptions& options,
											 const MonoBASweepOptions& sweep);

/** Fixed-width text table with a header comment (`#`) describing the run. */
std::string format_sweep_table(const std::vector<MonoBASweepRow>& rows, const problems::MonoBASceneOptions& scene,
							   const MonoBAOptions& options, const MonoBASweepOptions& sweep);

/** Options of `swba monoba`: one adjustment of a scene, or the prior-weight sweep. */
struct MonoBAAppOptions
{
	/** The scene (default: 3 cameras, 20 points, RNG seed 0); in the sweep the first of the seeds. */
	problems::MonoBASceneOptions scene;
	/** Gauge, anchors K, prior weight, LM options. The sweep ignores the gauge and the weight. */
	MonoBAOptions adjustment;
	/** Run the prior-weight sweep instead of one adjustment. Default false. */
	bool sweep = false;
	/** Sweep only: seeds scene.seed … scene.seed + sweep_seeds − 1 are averaged. Default 1. */
	int sweep_seeds = 1;
	/** Solves per run for the median time (one adjustment or each sweep entry). Default 1. */
	int repetitions = 1;
	/** Also write the report / sweep table to this file (empty: not written). */
	std::string out_path;

	/** The sweep's options: default weights and reference rows, sweep_seeds and repetitions. */
	MonoBASweepOptions sweep_options() const;
	/** Throws std::invalid_argument on an invalid scene, adjustment or sweep. */
	void validate() const;
};

/** Runs the adjustment (prints its report) or the sweep (prints its table) to `out` and writes
 * options.out_path ("Wrote <file>" on `log`). Returns the text printed. Throws std::invalid_argument on invalid options,
 * std::runtime_error when the adjustment fails (after printing the report) or the file cannot be
 * written. */
std::string run_monoba_app(const MonoBAAppOptions& options, std::ostream& out, std::ostream& log);
}  // namespace swba::apps
