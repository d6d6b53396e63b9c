/** \file monoba.h
 * Monocular bundle adjustment on a synthetic scene (seed 000's TestMonoBA) and the gauge study of
 * issue 2 (free / fixed / prior gauge, prior-weight sweep after Zhang, Gallego & Scaramuzza 2018).
 *
 * Scene: N cameras on a circular arc of radius r looking along +z (camera n at angle
 * θ_n = n·(π/2)/N about the world z axis, t_n = (r cos θ_n − r, r sin θ_n, sin 2θ_n)), M points
 * uniform in [−4, 4] × [−4, 4] × [4, 8] m. Camera poses are T_wc (camera-to-world, SE3Manifold).
 * Each point is an inverse depth λ (1-D, Group::Eliminable) in its first observing camera (the host);
 * its host bearing is fixed to the noisy first observation. Observations are on the normalised image
 * plane with Gaussian noise σ (per coordinate). The host observation defines the bearing; the other
 * observations become MonocularInverseDepthFactor's whitened by 1/σ. See doc/monoba.md. */
#pragma once

#include <swba/nonlinear/problem.h>
#include <swba/nonlinear/solver.h>

#include <mrpt/poses/CPose3D.h>

#include <Eigen/Core>
#include <string>
#include <vector>

#include <swba/nonlinear/gauge.h>

namespace swba::estimators
{
// GaugeMode, parse_gauge_mode, to_string(GaugeMode): swba/nonlinear/gauge.h (shared with the window).

struct MonoBASceneOptions
{
	/** Number of cameras N (≥ 2). Default 3. */
	int cameras = 3;
	/** Number of points M (≥ 1). Default 20. */
	int points = 20;
	/** Radius of the camera arc, m. Default 8. */
	double arc_radius_m = 8.0;
	/** σ of the observation noise on the normalised image plane (≥ 0). Default 1/460 (one pixel
	 * at a focal length of 460 px, EuRoC-like). Factors are whitened by 1/σ (by 460 when σ = 0). */
	double noise = 1.0 / 460.0;
	/** σ of the perturbation of the initial depths, m: λ₀ = 1/(z + n), n ~ N(0, σ²), redrawn while
	 * z + n < 0.5 m (seed 000 uses σ = 1). Default 1. */
	double depth_noise_m = 1.0;
	/** Initial pose perturbation of the cameras with index ≥ `pose_noise_from` (right perturbation,
	 * translation σ in m, rotation σ in rad per axis). Default 0 (poses start at ground truth, as seed 000). */
	double pose_noise_m = 0.0;
	double pose_noise_rad = 0.0;
	/** First camera index that receives pose noise (the anchors before it start at ground truth). Default 2. */
	int pose_noise_from = 2;
	/** RNG seed (std::mt19937). Default 0. */
	unsigned seed = 0;

	bool is_valid(std::string* why) const;
};

struct MonoBAObservation
{
	int camera = 0;
	Eigen::Vector2d uv;  ///< noisy observation on the normalised image plane
};

struct MonoBAPoint
{
	Eigen::Vector3d world;          ///< ground-truth position, m
	int host = 0;                   ///< first observing camera
	Eigen::Vector2d host_bearing;   ///< the host's noisy observation (fixed bearing [u, v, 1])
	double true_inverse_depth = 0;  ///< 1 / z of the true point in the host frame
	double initial_inverse_depth = 0;
	std::vector<MonoBAObservation> observations;  ///< by the other cameras (one factor each)
};

struct MonoBAScene
{
	MonoBASceneOptions options;
	std::vector<mrpt::poses::CPose3D> true_poses;     ///< T_wc
	std::vector<mrpt::poses::CPose3D> initial_poses;  ///< T_wc
	std::vector<MonoBAPoint> points;
};

/** Generates the scene; deterministic for a given seed. Points seen by fewer than two cameras
 * (z ≤ 0.1 m in the camera) are redrawn. Throws std::invalid_argument on invalid options. */
MonoBAScene make_monoba_scene(const MonoBASceneOptions& options);

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
	/** LM options. */
	SolverOptions solver;

	bool is_valid(std::string* why) const;
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
MonoBAProblem build_monoba_problem(const MonoBAScene& scene, const MonoBAOptions& options);

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

MonoBAErrors monoba_errors(const MonoBAScene& scene, const std::vector<mrpt::poses::CPose3D>& poses,
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
MonoBAResult run_monoba(const MonoBAScene& scene, const MonoBAOptions& options, int repetitions = 1);

/** The text report: options, solver summary, per-camera translations vs ground truth, per-point
 * inverse depth (ground truth / noisy initial / optimised) and the error summary. Deterministic
 * except for the times printed by the solver summary when `with_times`. */
std::string format_monoba_report(const MonoBAScene& scene, const MonoBAOptions& options,
								 const MonoBAResult& result, bool with_times = true);

/** The prior-weight sweep. */
struct SweepOptions
{
	/** Prior weights W; default 0, 1, 10, …, 1e10. */
	std::vector<double> weights;
	/** Seeds scene.seed, …, scene.seed + seeds − 1 are averaged. Default 1. */
	int seeds = 1;
	/** Solves per (seed, W) for the median time. Default 1. */
	int repetitions = 1;
	/** Also add reference rows for the Free and Fixed gauges. Default true. */
	bool reference_rows = true;

	SweepOptions();
	bool is_valid(std::string* why) const;
};

/** One row of the sweep table: means over the seeds. */
struct SweepRow
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
std::vector<SweepRow> run_prior_weight_sweep(const MonoBASceneOptions& scene, const MonoBAOptions& options,
											 const SweepOptions& sweep);

/** Fixed-width text table with a header comment (`#`) describing the run. */
std::string format_sweep_table(const std::vector<SweepRow>& rows, const MonoBASceneOptions& scene,
							   const MonoBAOptions& options, const SweepOptions& sweep);
}  // namespace swba::estimators
