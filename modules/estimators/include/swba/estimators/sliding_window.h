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

#include <swba/core/loss.h>
#include <swba/core/names.h>
#include <swba/eval/trajectory.h>
#include <swba/io/rawlog.h>
#include <swba/estimators/data_association.h>
#include <swba/estimators/pose_model.h>
#include <swba/estimators/sensor_noise.h>
#include <swba/nonlinear/gauge.h>
#include <swba/nonlinear/solver.h>
#include <swba/smoother/fixed_lag_smoother.h>
#include <swba/smoother/marginal_prior.h>

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <stdexcept>
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
	ConstantTime,
	/** As ConstantTime, but a landmark that leaves the state is kept in a map as its marginal (world
	 * point, 3×3 covariance), and one seen again re-enters from it (a prior factor of that marginal):
	 * the cost per step stays bounded and the map is remembered, without its cross-correlations (an
	 * approximation, doc/window.md "Map policy"). With data association the map's landmarks are
	 * candidates too. Needs the fixed or prior gauge. */
	Map
};
constexpr std::array<EnumName<LandmarkPolicy>, 3> enum_names(LandmarkPolicy)
{
	return {{{LandmarkPolicy::Slam, "slam"}, {LandmarkPolicy::ConstantTime, "constant-time"}, {LandmarkPolicy::Map, "map"}}};
}

LandmarkParameterization parse_landmark_parameterization(const std::string& s);  ///< "inverse-depth" | "xyz"
LandmarkPolicy parse_landmark_policy(const std::string& s);                      ///< "slam" | "constant-time" | "map"
std::string to_string(LandmarkParameterization p);
std::string to_string(LandmarkPolicy p);

struct SlidingWindowOptions
{
	/** Number of poses kept in the window (W ≥ 2); 0 = unbounded (no marginalisation). Default 10. */
	int window_size = 10;
	/** Poses of the window re-linearised at every step: the newest min(K, W). The older poses of the
	 * window stay in the estimate, frozen at their linearisation, as the Gaussian conditional they left
	 * the re-linearised part with, and are smoothed by back-substitution after each solve; a pose leaves
	 * the lagged output at lag W either way (doc/window.md, "Re-linearised poses"). 0 = all W.
	 * Applies to the SLAM policy with the fixed or prior gauge; the others re-linearise the whole window
	 * (see relinearized_window()). Default 2: the new pose and the one before it. */
	int relinearized_poses = 2;
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
	/** 6D or planar robot (doc/window.md, "Planar rawlogs"). Planar: SE(2) poses, landmarks as world
	 * points at the sensor's height (the landmarks option does not apply: a 2D reading measures the
	 * range, so there is no depth to parameterise), readings (range, yaw) with σ_range, σ_yaw only.
	 * Default Auto: decided by the first step (io::is_planar_step with 2D odometry). */
	PoseModel model = PoseModel::Auto;
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
	/** χ² gate of the bearing-range readings (doc/outliers.md). Window: a reading of a known landmark
	 * enters only if the squared Mahalanobis distance of its innovation against the current estimate
	 * (covariance: the sensor noise, the landmark's estimate, the new pose's odometry) is at most the
	 * χ² quantile at gate_probability with one degree of freedom per reading row (reading_dof: 3 in 6D,
	 * 2 in the planar model); a gated reading is re-tested after each solve while its pose is
	 * in the window and dropped for good when the pose leaves. A landmark enters with two mutually
	 * consistent readings: its first reading waits until one agrees with it (a reading alone cannot be
	 * tested, and an outlier first reading would otherwise hold the landmark wrong and gate every good
	 * reading of it). Batch: every reading is re-tested against each solution and the problem solved
	 * again until the admitted set settles. Gated readings never reach the marginal prior. Default false: on real logs a drifting estimate
	 * gates correct readings, which lets it drift further (doc/realdata.md); the robust loss takes outliers. */
	bool gate_readings = false;
	/** Probability of the χ² gate, in (0, 1): the share of correct readings that pass. Default 0.999. */
	double gate_probability = 0.999;
	/** Robust loss of every range-bearing factor (window and batch); robustified factors enter the
	 * marginal prior with their IRLS weight at the current estimate. Default Cauchy: a gross reading's influence vanishes instead of being cut by a
	 * hard decision that can cascade (doc/realdata.md). */
	RobustLoss robust_loss = RobustLoss::Cauchy;
	/** Scale of the robust loss, in whitened units: √χ²_dof(robust_probability) with dof = reading_dof,
	 * the radius that holds this share of correct readings (residuals beyond it are down-weighted), in
	 * (0, 1). Default 0.99: with the loss on by default, 0.95 down-weighted enough correct readings of
	 * the simulated rawlogs to cost them up to 2.7 % of their accuracy (doc/realdata.md). */
	double robust_probability = 0.99;
	/** Recover marginal covariances: the window each step (the newest pose after its solve, the oldest
	 * when it leaves), the batch at its solution, both for the final landmarks. Cost and gauge:
	 * doc/window.md, "Covariances". Default true. */
	bool covariances = true;
	/** Which landmark each reading comes from (doc/association.md): its own ID, or data association
	 * against the window's estimate, gated at gate_probability. Default Auto: the readings' IDs when
	 * the first step with readings has an ID for each, else Jcbb. The batch uses the IDs it is given
	 * (swba run gives it the window's decisions). */
	DataAssociation association = DataAssociation::Auto;
	/** Data association only: after each solve, a reading of a window pose that fails the χ² gate against
	 * the landmark it was given and passes it against another is moved there (doc/association.md,
	 * "Re-association"). Decisions are revisited while their pose is in the window, not after it left.
	 * Default true. */
	bool reassociate = true;
	/** Data association only: a reading the association leaves unmatched, which would start a landmark,
	 * is tested again — against the state's landmarks no other reading of its step took — with the new
	 * pose's covariance multiplied by this factor (its σ by the square root) and the landmarks' and the
	 * reading's own noise unchanged, so that the step's readings are still tested jointly as tightly.
	 * Real odometry makes the pose overconfident relative to the map (errors correlated over steps:
	 * 3.5–7 times in variance on the real logs), and a reading of a known landmark that starts a new one
	 * is what loses the map there (doc/realdata.md). 1 = off. Default 9 (the pose's σ × 3). */
	double association_pose_inflation = 9.0;
	/** A pose whose readings include one of a landmark given fewer than this many readings so far stays
	 * re-linearised (beyond relinearized_poses, within window_size), with a robust loss. Such a
	 * landmark is still fitted to those readings, so marginalising them would freeze their robust weight
	 * at a near-zero residual, where the later readings (and the batch) give them less: on real logs
	 * that is most of the gap to the causal optimum (doc/realdata.md). 0 = never. Default 30. */
	int young_landmark_readings = 30;
	/** Run the young_landmark_readings rule only until a sequential test (Wald's, on the whitened squared
	 * residuals of the readings entering the marginal prior: χ²_dof against 2·χ²_dof, error
	 * probabilities 1e-3) decides that the readings fit their declared noise: under the declared model
	 * the window is then the one without the rule after a few dozen readings. false: the rule runs for
	 * the whole run. Default true. */
	bool young_readings_test = true;

	/** The poses re-linearised at every step: min(relinearized_poses, window_size) for the SLAM policy
	 * with the fixed or prior gauge, else window_size (0: unbounded). The constant-time and map policies
	 * marginalise the landmarks no window pose observes, so for them W is how long a landmark is kept;
	 * the free gauge holds the whole window's gauge after each solve. */
	int relinearized_window() const;
	/** The χ² bound of the gate for readings of `dof` rows (reading_dof of the model). */
	double gate_threshold(int dof) const;
	/** The squared scale of the robust loss for readings of `dof` rows: χ²_dof(robust_probability). */
	double robust_scale_squared(int dof) const;
	/** The robust loss of the range-bearing factors of `dof` rows (nullptr for None). */
	std::shared_ptr<const LossFunction> reading_loss(int dof) const;

	static SolverOptions default_solver_options();
	/** Throws std::invalid_argument naming the bad option. */
	void validate() const;
	/** The INI keys of the window's own options in `section`: landmarks, model, gauge, gauge_prior_weight,
	 * marginalization_threshold. The members solver, sensor and odometry have their own keys
	 * (SolverOptions::ini_keys etc.); window_size, policy and FEJ are chosen per run by the application.
	 * Also the outlier keys: gate, gate_probability, robust_loss, robust_probability; covariances;
	 * association, reassociate and association_pose_inflation; young_landmark_readings and
	 * young_readings_test. */
	static IniKeys<SlidingWindowOptions> ini_keys(const std::string& section);
};

/** What one process() call did. */
struct StepSummary
{
	std::size_t step = 0;
	int iterations = 0;
	TerminationType termination = TerminationType::NotRun;  ///< of this step's LM solve
	std::string solver_message;                             ///< the solver's reason, one line
	/** Cost of the LM problem before and after the solve (with prior-only landmarks eliminated, of the
	 * reduced problem: the prior's part differs from the full prior's by a constant). */
	double initial_cost = 0, final_cost = 0;
	double seconds = 0;             ///< whole process() call
	double solve_seconds = 0;       ///< LM solve
	double marginalization_seconds = 0;
	double covariance_seconds = 0;  ///< covariance recovery (part of `seconds`, not of solve_seconds)
	int window_poses = 0;
	int landmarks = 0;              ///< landmark variables in the state
	int prior_rank = 0;             ///< rows of the marginal prior (0: none)
	int prior_variables = 0;
	int readings = 0;               ///< observations added this step
	int reanchored = 0;             ///< landmarks re-anchored this step (including those switched to world XYZ)
	int landmarks_to_world = 0;     ///< of these, landmarks in the prior switched to world XYZ (inverse depth only)
	int marginalized_landmarks = 0; ///< landmarks marginalised this step (ConstantTime, Map)
	int landmarks_from_map = 0;     ///< landmarks seen again that re-entered the state from the map (Map)
	int landmarks_not_mapped = 0;   ///< of the marginalised, those whose marginal could not be kept (Map)
	int prior_only_landmarks = 0;   ///< landmarks held out of this step's LM solve (eliminate_prior_only_landmarks)
	int gated = 0;                  ///< readings held out by the χ² gate on arrival this step
	int readmitted = 0;             ///< held readings that passed the gate after this step's solve and entered
	int reassociated = 0;           ///< readings moved to another landmark after this step's solve (reassociate)
	int down_weighted = 0;          ///< readings that entered the marginal prior this step beyond the loss's scale
	/** Poses kept re-linearised beyond relinearized_poses after this step (young landmarks' readings). */
	int kept_relinearized = 0;
	/** Factors the marginalisation could not evaluate at the current values (residual undefined or not
	 * finite there): dropped with the marginalised variables, their information lost. Counted, never
	 * silent: swba run reports the total as a note. */
	int unevaluable_factors = 0;
};

/** What happened to the bearing-range readings of a run (totals; see SlidingWindowOptions::gate_readings). */
struct ReadingCounts
{
	std::size_t readings = 0;       ///< readings processed
	/** Window: readings held out by the gate on arrival; batch: readings outside the gate at the final
	 * solution. */
	std::size_t gated = 0;
	std::size_t readmitted = 0;     ///< window: of the gated, those that passed after a later solve
	std::size_t reassociated = 0;   ///< window, data association: readings moved to another landmark (reassociate)
	/** Window, data association: readings individually compatible with two landmarks or more when
	 * they arrived (inside the χ² gate of each against the window's joint prediction), which one
	 * reading alone cannot decide between. */
	std::size_t ambiguous = 0;
	/** Window, data association: readings left unmatched by the association that the second test with
	 * the pose's covariance inflated gave a landmark of the state (association_pose_inflation). */
	std::size_t rematched = 0;
	/** Window, JCBB: steps whose association search stopped at its node budget and kept the best
	 * pairing found so far (estimators::associate). */
	std::size_t association_cut = 0;
	/** First readings of a landmark that no later reading confirmed while their pose was in the window
	 * (window only; most are landmarks seen once, which carry no information). */
	std::size_t unconfirmed = 0;
	/** Readings never used by the estimate: gated and not re-admitted, plus the unconfirmed. */
	std::size_t excluded = 0;
	/** Readings whose whitened residual lay beyond the robust loss's scale (Huber weight < 1, Cauchy
	 * weight < 1/2) when they entered the marginal prior (window; the readings still in the window at
	 * the end, all of them at W = inf, at the final estimate) / at the solution (batch). */
	std::size_t down_weighted = 0;
	/** Window: steps after which poses were kept re-linearised for young landmarks' readings
	 * (SlidingWindowOptions::young_landmark_readings). */
	std::size_t young_held_steps = 0;
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
	/** Poses in the window, oldest first: (time, pose); those of the linear tail (beyond the re-linearised
	 * poses) at their smoothed estimates. */
	std::vector<std::pair<double, mrpt::poses::CPose3D>> window_poses() const;
	/** Current landmark estimates (world XYZ) by landmark ID. */
	std::map<std::int32_t, Eigen::Vector3d> landmarks() const;

	/** The estimate of the initial pose (t = 0; the origin under the fixed gauge, free to move under
	 * the others): its value when it left the window, or its current value while it is in it (the
	 * origin before the first step). */
	mrpt::poses::CPose3D initial_pose() const;
	/** Each pose as estimated right after its own step (t = k + 1). */
	const eval::Trajectory& online_trajectory() const;
	/** Each pose as estimated when it left the window (complete after finish()). */
	const eval::Trajectory& lagged_trajectory() const;
	/** The marginal covariance of each pose of online_trajectory() / lagged_trajectory() (same order) as
	 * the window had it at that moment: right after the step's solve / when the pose left the window at
	 * lag W, in the window's model (the re-linearised poses' problem times the linear tail's
	 * conditionals, doc/window.md "Re-linearised poses"; the poses flushed by finish(): at the final
	 * state). Empty with options().covariances off. */
	const std::vector<PoseCovariance>& online_covariances() const;
	const std::vector<PoseCovariance>& lagged_covariances() const;
	/** The landmarks in the state with their marginal covariance at the current estimate (one
	 * factorisation of the window's whole system, prior-only landmarks included). */
	std::map<std::int32_t, LandmarkEstimate> landmark_estimates();
	const std::vector<StepSummary>& step_summaries() const;
	/** The landmark ID each reading of step k was given (data association, or the reading's own ID):
	 * assigned_ids()[k] in the order of that step's readings (empty for a step without readings). */
	std::vector<std::vector<std::int32_t>> assigned_ids() const;
	/** Totals over the steps so far (readings still held in the window count as excluded after finish()). */
	ReadingCounts reading_counts() const;
	const SlidingWindowOptions& options() const;

	/** The fixed-lag smoother underneath: the window's factor graph (factors, values, first
	 * estimates), its states and its marginal prior, as the next solve will see them. */
	const smoother::FixedLagSmoother& smoother() const;

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

/** Bad data at one step (e.g. no odometry, a non-positive sensor noise), found while building the
 * problem: what() names the step, step() is its index k. */
class StepError : public std::invalid_argument
{
   public:
	StepError(std::size_t step, const std::string& what) : std::invalid_argument(what), step_(step) {}
	std::size_t step() const { return step_; }

   private:
	std::size_t step_;
};

/** Result of run_batch(). */
struct BatchResult
{
	eval::Trajectory trajectory;
	Summary summary;                    ///< of the last solve round
	int rounds = 1;                     ///< solves (one more each time the gate changed the admitted readings)
	ReadingCounts counts;
	mrpt::poses::CPose3D initial_pose;  ///< the initial pose's estimate (t = 0, not in `trajectory`)
	double seconds = 0;
	/** options.covariances: per pose of `trajectory`, its marginal covariance at the solution, and the
	 * landmarks with theirs (one factorisation of the full problem, Schur on the landmarks). */
	std::vector<PoseCovariance> covariances;
	std::map<std::int32_t, LandmarkEstimate> landmarks;
	double covariance_seconds = 0;  ///< included in `seconds`
};

/** The same factors over the whole rawlog in one problem (window = ∞), initialised by dead
 * reckoning and first observations, solved (with gate_readings: re-gated and solved again while the
 * gate changes the admitted readings, at most 6 solves). `max_iterations` overrides the options' solver.
 * `start` (optional): initial poses by time (t = step.time(); the initial pose keeps the gauge's) in
 * place of dead reckoning, e.g. a window's lagged trajectory; steps it lacks are dead-reckoned from
 * the previous pose, and every landmark is initialised from its first reading at its pose's start.
 * A batch started from dead reckoning can stop in a local minimum on real logs (large heading drift);
 * compare Summary::final_cost of the two starts. Throws StepError for bad data at a step. */
BatchResult run_batch(const io::Rawlog& rawlog, const SlidingWindowOptions& options, int max_iterations = 100,
					  const eval::Trajectory* start = nullptr);

/** "Online, W = ∞": re-solves the whole history after every step and keeps the newest pose (the
 * causal optimum the online window trajectory is measured against). O(steps²): for evaluation.
 * Throws StepError for bad data at a step. `counts` (optional) receives the run's reading counts,
 * `initial_pose` (optional) the final estimate of the initial pose. */
eval::Trajectory run_full_history_causal(const io::Rawlog& rawlog, const SlidingWindowOptions& options,
										 ReadingCounts* counts = nullptr, mrpt::poses::CPose3D* initial_pose = nullptr);
}  // namespace swba::estimators
