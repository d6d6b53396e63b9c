/** \file sliding_window.h
 * Sliding-window estimator for range-bearing SLAM on MRPT rawlogs (odometry + landmark observations),
 * with marginalisation of the oldest pose into a linearised prior (J, e, x_lin), first-estimate
 * Jacobians, inverse-depth (or XYZ) landmarks and two landmark policies, on the sensor-free fixed-lag
 * machinery of swba/smoother/fixed_lag_smoother.h. The batch estimator is the same factor graph with
 * an unbounded window, solved once at the end.
 *
 * Typical use (an online loop):
 * \code
 *   swba::estimators::SlidingWindowEstimator est(options);
 *   for (const auto& step : rawlog.steps) {
 *     est.process(step);                 // one LM solve over the window (+ one marginalisation)
 *     mrpt::poses::CPose3D now = est.current_pose();
 *   }
 *   est.finish();                        // flush the poses still in the window to the lagged output
 * \endcode */
#pragma once

#include <swba/core/names.h>
#include <swba/eval/trajectory.h>
#include <swba/io/rawlog.h>
#include <swba/estimators/sensor_noise.h>
#include <swba/nonlinear/gauge.h>
#include <swba/nonlinear/solver.h>
#include <swba/smoother/marginal_prior.h>

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>


namespace swba::estimators
{
enum class LandmarkParameterization
{
	/** [azimuth, elevation, inverse range] in the anchor (first observing) pose's sensor frame. When the
	 * anchor leaves the window a landmark not yet in the marginal prior is re-anchored exactly (its
	 * factors rewritten) to the newest pose that observes it; one already in the prior is switched to
	 * world XYZ by a first-order change of variables in the prior (once: repeated re-anchoring of
	 * prior landmarks compounded linearisation errors until the window diverged on dense maps). */
	InverseDepth,
	Xyz            ///< world point
};
constexpr std::array<EnumName<LandmarkParameterization>, 2> enum_names(LandmarkParameterization)
{
	return {{{LandmarkParameterization::InverseDepth, "inverse-depth"}, {LandmarkParameterization::Xyz, "xyz"}}};
}

enum class LandmarkPolicy
{
	/** Every landmark stays in the state; only poses are marginalised, so the prior links the
	 * landmarks (like the EKF's covariance) and W → ∞ is the batch problem. Cost grows with the map. */
	Slam,
	/** Landmarks that no pose left in the window observes are marginalised with the oldest pose
	 * (VIO style): the state and the cost per step stay bounded, the map is forgotten. */
	ConstantTime
};
constexpr std::array<EnumName<LandmarkPolicy>, 2> enum_names(LandmarkPolicy)
{
	return {{{LandmarkPolicy::Slam, "slam"}, {LandmarkPolicy::ConstantTime, "constant-time"}}};
}


LandmarkParameterization parse_landmark_parameterization(const std::string& s);  ///< "inverse-depth" | "xyz"
LandmarkPolicy parse_landmark_policy(const std::string& s);                      ///< "slam" | "constant-time"
std::string to_string(LandmarkParameterization p);
std::string to_string(LandmarkPolicy p);

struct SlidingWindowOptions
{
	/** Number of poses kept in the window (W ≥ 2); 0 = unbounded (no marginalisation). Default 10. */
	int window_size = 10;
	/** Default InverseDepth. */
	LandmarkParameterization landmarks = LandmarkParameterization::InverseDepth;
	/** Default Slam (the more accurate one, see doc/window.md). */
	LandmarkPolicy policy = LandmarkPolicy::Slam;
	/** Evaluate every factor touching a state in the prior at that state's first estimate. Default true. */
	bool first_estimate_jacobians = true;
	/** Gauge of the window: Fixed (the first pose is constant), Free, or Prior (an SE(3) prior on
	 * the first pose with information gauge_prior_weight·I). Default Fixed. */
	GaugeMode gauge = GaugeMode::Fixed;
	/** Information (per tangent coordinate) of the gauge prior, GaugeMode::Prior only. Default 1e8. */
	double gauge_prior_weight = 1e8;
	/** Sensor noise (m, rad); a value ≤ 0 uses the observation's own. Default: all the observation's. */
	SensorNoiseOptions sensor;
	/** Floors of the odometry covariance. */
	io::OdometryInformationOptions odometry;
	/** Relative eigenvalue threshold of the marginal prior (see swba::marginalize). Default 1e-12. */
	double marginalization_threshold = 1e-12;
	/** LM options of the per-step solve. Defaults: max_iterations 10, function_tolerance 1e-7. With
	 * linear_solver Auto and a prior over several landmarks (no Schur elimination possible) the window
	 * asks for DenseNormal directly (SparseNormal above dense_max_dim), which is what Auto would pick. */
	SolverOptions solver = default_solver_options();
	/** Landmarks connected to nothing but the marginal prior (no window pose observes them; SLAM policy)
	 * are eliminated from each LM solve exactly: the solve sees the prior's marginal over the other
	 * variables, and those landmarks are then set to their conditional optimum (doc/window.md,
	 * "Cost per step"). Same optimum, a much smaller dense system. Default true. */
	bool eliminate_prior_only_landmarks = true;

	static SolverOptions default_solver_options();
	/** Throws std::invalid_argument naming the bad option. */
	void validate() const;
	/** The INI keys of the window's own options in `section`: landmarks, gauge, gauge_prior_weight,
	 * marginalization_threshold. The members solver, sensor and odometry have their own keys
	 * (SolverOptions::ini_keys etc.); window_size, policy and FEJ are chosen per run by the application. */
	static IniKeys<SlidingWindowOptions> ini_keys(const std::string& section);
};

/** What one process() call did. */
struct StepSummary
{
	std::size_t step = 0;
	int iterations = 0;
	/** Cost of the LM problem before and after the solve (with prior-only landmarks eliminated, of the
	 * reduced problem: the prior's part differs from the full prior's by a constant). */
	double initial_cost = 0, final_cost = 0;
	double seconds = 0;             ///< whole process() call
	double solve_seconds = 0;       ///< LM solve
	double marginalization_seconds = 0;
	int window_poses = 0;
	int landmarks = 0;              ///< landmark variables in the state
	int prior_rank = 0;             ///< rows of the marginal prior (0: none)
	int prior_variables = 0;
	int readings = 0;               ///< observations added this step
	int reanchored = 0;             ///< landmarks re-anchored this step (including those switched to world XYZ)
	int landmarks_to_world = 0;     ///< of these, landmarks in the prior switched to world XYZ (inverse depth only)
	int marginalized_landmarks = 0; ///< landmarks marginalised this step (ConstantTime)
	int prior_only_landmarks = 0;   ///< landmarks held out of this step's LM solve (eliminate_prior_only_landmarks)
	/** Factors the marginalisation could not evaluate at the current values (residual undefined or not
	 * finite there): dropped with the marginalised variables, their information lost. Counted, never
	 * silent: swba run reports the total as a note. */
	int unevaluable_factors = 0;
};

class SlidingWindowEstimator
{
   public:
	/** Throws std::invalid_argument on invalid options. Starts with the first pose at the origin. */
	explicit SlidingWindowEstimator(const SlidingWindowOptions& options);
	~SlidingWindowEstimator();
	SlidingWindowEstimator(const SlidingWindowEstimator&) = delete;
	SlidingWindowEstimator& operator=(const SlidingWindowEstimator&) = delete;

	/** Adds the step's pose (odometry) and observations, optimises the window and, when the window
	 * is full, marginalises the oldest pose. Cost: one LM solve over the window's state (dense in the
	 * prior's landmarks with the Slam policy) and one dense marginalisation. Throws
	 * std::invalid_argument on a step without odometry after the first one. */
	const StepSummary& process(const io::RawlogStep& step);
	/** Moves the poses still in the window to the lagged trajectory. Call once at the end. */
	void finish();

	/** The newest pose's current estimate. */
	mrpt::poses::CPose3D current_pose() const;
	/** Poses in the window, oldest first: (time, pose). */
	std::vector<std::pair<double, mrpt::poses::CPose3D>> window_poses() const;
	/** Current landmark estimates (world XYZ) by landmark ID. */
	std::map<std::int32_t, Eigen::Vector3d> landmarks() const;

	/** The estimate of the initial pose (t = 0; the origin under the fixed gauge, free to move under
	 * the others): its value when it left the window, or its current value while it is in it. */
	mrpt::poses::CPose3D initial_pose() const;
	/** Each pose as estimated right after its own step (t = k + 1). */
	const eval::Trajectory& online_trajectory() const;
	/** Each pose as estimated when it left the window (complete after finish()). */
	const eval::Trajectory& lagged_trajectory() const;
	const std::vector<StepSummary>& step_summaries() const;
	const SlidingWindowOptions& options() const;

	/** Consistency diagnostics of the marginal prior (empty matrices while there is none). */
	/** The marginal prior as stored: its square-root form (J, e, x_lin) and its information (H, b). */
	const smoother::MarginalPrior& marginal_prior() const;
	/** Its information H = JᵀJ over its variables, in their tangent coordinates. */
	Eigen::MatrixXd prior_information() const;
	/** The 6 global SE(3) motions (translation, rotation) as columns in the same coordinates, at the
	 * prior's linearisation point. The window's cost is invariant under them, so a prior that does not
	 * invent information about the global pose has H·N ≈ 0; ‖H·N‖ / ‖H‖ measures the leak. */
	Eigen::MatrixXd prior_gauge_directions() const;

   private:
	struct Impl;
	std::unique_ptr<Impl> impl_;
};

/** Result of run_batch(). */
struct BatchResult
{
	eval::Trajectory trajectory;
	Summary summary;
	mrpt::poses::CPose3D initial_pose;  ///< the initial pose's estimate (t = 0, not in `trajectory`)
	double seconds = 0;
};

/** The same factors over the whole rawlog in one problem (window = ∞), initialised by dead
 * reckoning and first observations, solved once. `max_iterations` overrides the options' solver. */
BatchResult run_batch(const io::Rawlog& rawlog, const SlidingWindowOptions& options, int max_iterations = 100);

/** "Online, W = ∞": re-solves the whole history after every step and keeps the newest pose (the
 * causal optimum the online window trajectory is measured against). O(steps²): for evaluation.
 * `initial_pose` (optional) receives the final estimate of the initial pose. */
eval::Trajectory run_full_history_causal(const io::Rawlog& rawlog, const SlidingWindowOptions& options,
										 mrpt::poses::CPose3D* initial_pose = nullptr);
}  // namespace swba::estimators
