/** \file range_bearing_graph.h
 * (private to the estimators module) Range-bearing SLAM as a factor graph on a fixed-lag smoother: one
 * SE(3) pose per step (odometry between consecutive poses, the first pose gauge-fixed as the options
 * say), one landmark variable per landmark ID (inverse depth in its anchor's sensor frame, or world
 * XYZ), one range-bearing factor per reading. The window (SlidingWindowEstimator) and the batch run
 * (run_batch) are both built on it.
 *
 * The graph owns the smoother's problem and is the only one to change it; the landmarks' records and
 * their readings' bookkeeping (held, unconfirmed, the linear tail's counts, the map policy's map) live
 * in a LandmarkStore it holds, which callers see read-only through landmarks(); the χ² gate's maths
 * (distances, the newest pose's prediction and robust centre) in a ReadingGate. What the graph keeps of
 * the gate is the policy: which readings are tested when, and what becomes of those outside. Data
 * association's predictions of the landmarks come from a LandmarkPredictor, its decisions from
 * match_readings (which landmark a reading is given) and reassociation_moves; the graph gathers
 * their inputs and applies the decisions (IDs, factors moved, landmarks removed).
 *
 * Planar model (PoseModel::Planar): the same graph restricted to the plane (swba/factors/planar.h):
 * poses updated in (ρx, ρy, ωz), landmarks as world points updated in (x, y) at the sensor's height,
 * odometry factors on (ρx, ρy, ωz) with the 3×3 planar information, readings on (range, yaw). */
#pragma once

#include "landmark_prediction.h"
#include "landmark_store.h"
#include "reading_gate.h"

#include <swba/estimators/data_association.h>
#include <swba/estimators/sliding_window.h>
#include <swba/factors/range_bearing.h>
#include <swba/smoother/fixed_lag_smoother.h>

#include <cstddef>
#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace swba::estimators::detail
{
class RangeBearingGraph
{
   public:
	/** Validates `options` (throws std::invalid_argument) and adds the first pose at the origin (time 0)
	 * as the first state, constant or with a pose prior as options.gauge says; with PoseModel::Auto
	 * that happens at the first add_step, once the model is known. */
	explicit RangeBearingGraph(const SlidingWindowOptions& options);

	/** The model chosen (Auto before the first step). */
	PoseModel model() const { return model_; }
	/** Rows of a reading in the model chosen (estimators::reading_dof; 3 before the first step). */
	int reading_dof() const { return estimators::reading_dof(model_); }
	/** The pose of variable `var` (an SE(3) or planar pose variable). */
	mrpt::poses::CPose3D pose(VariableId var) const;

	const SlidingWindowOptions& options() const { return opt_; }
	smoother::FixedLagSmoother& smoother() { return smoother_; }
	const smoother::FixedLagSmoother& smoother() const { return smoother_; }

	/** Adds the step's pose (dead reckoning from the newest pose), its odometry factor and one factor
	 * per reading (a new landmark initialised from its first reading); counts readings in `sum`. With
	 * gate_on_entry() each reading passes admit_reading() first. Throws std::invalid_argument on a step
	 * without odometry or with a non-positive sensor noise, and in the planar model on a step that is
	 * not planar (3D odometry, a reading with pitch). */
	void add_step(const io::RawlogStep& step, StepSummary& sum);

	/** Whether add_step gates readings on arrival (the window: options().gate_readings). The batch
	 * turns it off and gates after each solve with regate_all(). */
	bool gate_on_entry() const { return gate_on_entry_; }
	void set_gate_on_entry(bool on) { gate_on_entry_ = on; }
	/** Initial values of the poses add_step() creates, by time, in place of dead reckoning (the batch
	 * started from another estimate); a time without one is dead-reckoned. */
	void set_pose_guesses(std::map<double, mrpt::poses::CPose3D> guesses) { pose_guesses_ = std::move(guesses); }
	/** After a solve: the held readings that now pass the gate enter the window (counted in
	 * sum.readmitted; their factors act from the next solve). */
	void readmit_held(StepSummary& sum);
	/** Data association only (nn, jcbb; options().reassociate), after a solve, at the current estimate:
	 * a reading in the window that fails the χ² gate against the landmark it was given and passes it
	 * against another (the one it fits best, which has no reading of the same step) is moved there; and
	 * a landmark not in the marginal prior all of whose readings pass the gate against an older
	 * landmark, observed at none of their steps, is merged into it (a duplicate). assigned_ids()
	 * follows; the factors act from the next solve; a landmark left with no reading and not in the prior
	 * is removed. Moved readings are counted in sum.reassociated. */
	void reassociate(StepSummary& sum);
	/** Before pose step `k` is marginalised: its held readings and unconfirmed first readings are
	 * dropped for good (counted). */
	void expire_readings_at(std::size_t k);
	/** The readings of pose step k (leaving the re-linearised poses for the linear tail) still count
	 * for their landmarks' gate (LandmarkStore::window_readings) until release_tail_readings() at lag W. */
	void hold_tail_readings(std::size_t k) { store_.hold_tail_readings(k); }
	/** The oldest pose of the linear tail left the window: its readings no longer count. */
	void release_tail_readings() { store_.release_tail_readings(); }
	/** Batch: re-tests every reading against the current estimate; readings outside the gate lose their
	 * factor, held ones inside it get one back (a landmark keeps at least its best-fitting reading).
	 * Returns whether the admitted set changed. */
	bool regate_all();
	/** Rebuilds every admitted reading's factor with robust loss `loss` (null: least squares). */
	void set_reading_loss(std::shared_ptr<const LossFunction> loss);
	/** Readings among `factors` with a robust loss whose whitened residual lies beyond the loss's scale
	 * a (‖r‖² > a² = χ²_dof(robust_probability), dof = reading_dof()) at the current values: Huber's weight is < 1 there and
	 * Cauchy's < 1/2 (Cauchy's weight is below 1 for every non-zero residual, so "< 1" would count all). */
	int count_down_weighted(const std::set<FactorId>& factors) const;
	/** The whitened squared residuals ‖r‖² of the readings among `factors` with a robust loss, at the
	 * current values (readings that cannot be evaluated there are left out). */
	std::vector<double> robust_squared_residuals(const std::set<FactorId>& factors) const;
	/** How many of `squares` (robust_squared_residuals) lie beyond the loss's scale. */
	int count_beyond_scale(const std::vector<double>& squares) const;
	/** The reading factors of pose step `k` and of the landmarks `leaving` (what marginalising k takes). */
	std::set<FactorId> reading_factors_leaving(std::size_t k, const std::set<VariableId>& leaving) const;
	/** Counts so far (excluded: readings dropped for good; call finish_counts() at the end). */
	const ReadingCounts& counts() const { return counts_; }
	/** Counts the readings still held or unconfirmed as excluded (the run is over). */
	void finish_counts();

	/** The association in use: options().association, Auto resolved at the first step with readings
	 * (Ids when every reading of that step has an ID, else Jcbb). */
	DataAssociation association() const { return association_; }
	/** The landmark ID each reading of pose step k was given (its own ID with DataAssociation::Ids), in
	 * the step's reading order; empty for steps without readings. */
	const std::vector<std::vector<std::int32_t>>& assigned_ids() const { return assigned_ids_; }

	/** Every pose ever created, by step (0 = initial). */
	const std::vector<PoseRecord>& poses() const { return poses_; }
	/** Step of the pose variable `var`. */
	std::size_t step_of(VariableId pose_var) const { return step_of_.at(pose_var); }
	/** The landmarks in the state, by ID (changed only through the graph). */
	const LandmarkStore& landmarks() const { return store_; }
	bool is_landmark(VariableId v) const { return store_.is_landmark(v); }
	/** How the smoother handles `v` while only its prior touches it: landmarks are eliminated, or stored
	 * with the SLAM policy and known IDs (SlidingWindowOptions::eliminate_prior_only_landmarks). */
	smoother::PriorOnly prior_only(VariableId v) const;
	/** A landmark variable holding a world point (XYZ parameterisation, or switched to world XYZ). */
	bool is_world_point(VariableId v) const;
	/** World XYZ of every landmark by ID. */
	std::map<std::int32_t, Eigen::Vector3d> landmark_positions() const;

	/** Forgets the landmark of variable `v` (being marginalised); false when `v` is no landmark. */
	bool forget_landmark(VariableId v);
	/** Map policy: keeps the marginals of the landmarks of `vars` (about to be marginalised) in the map,
	 * from one covariance recovery of the current problem. Returns how many could not be kept (their
	 * covariance not recovered or not positive definite): they are forgotten, as ConstantTime does. */
	int keep_in_map(const std::set<VariableId>& vars);
	/** Drops the observations whose factors are in `removed`. */
	void forget_observations(const std::set<FactorId>& removed) { store_.forget_observations(removed); }

	/** Re-anchors inverse-depth landmark `id`, which is not in the marginal prior, to pose step `b`: an
	 * exact rewrite of its factors. (A landmark in the prior is switched to world XYZ instead.) */
	void reanchor(std::int32_t id, std::size_t b);
	/** Switches inverse-depth landmark `id`, which is in the marginal prior and whose anchor a is about
	 * to be marginalised, to world XYZ p: an exact rewrite of its factors, and a first-order change of
	 * variables λ = g(T_a, p) (p seen from a's sensor, as inverse depth) in the prior, at the first
	 * estimates. T_a is marginalised right after, so the prior never depends on a re-anchoring again:
	 * a landmark in the prior changes parameterisation once, not every time its anchor leaves. */
	void convert_to_world_xyz(std::int32_t id);

	/** The six global rigid motions p ↦ p + u + w × p (columns [u, w]) in the tangent coordinates of
	 * variable `v` at value `x`: a pose's right perturbation, a world point's offset; zero rows for an
	 * inverse-depth landmark (relative to its anchor). The graph's cost is invariant under them. */
	Eigen::MatrixXd gauge_directions(VariableId v, const double* x) const;
	/** The frame a free-gauge solve is held in: each non-constant variable's linearisation point (its
	 * first estimate once frozen, else its current value). */
	std::map<VariableId, std::vector<double>> gauge_snapshot() const;
	/** Free gauge: a solve's step is determined only up to the global motions, along which LM's
	 * damping moves it a little at every iteration; over a run the window's frame random-walks away
	 * from the frame its first estimates (and the marginal prior's Jacobian, whose null space is the
	 * global motions there) were taken in. This fits the rigid motion that best explains the
	 * displacement of the variables from `before` (least squares in their tangent coordinates) and
	 * applies its inverse to every pose and world point: the cost does not change, and the window
	 * stays in the frame of its first estimates. Variables not in `before` (added since) are moved too
	 * but do not enter the fit. */
	void hold_gauge(const std::map<VariableId, std::vector<double>>& before);

	/** @name Covariances (window_covariance.cpp)
	 * @{ */
	/** The covariances of `groups` at the current values (FixedLagSmoother::covariances: a fresh
	 * linearisation; a group may name a pose of the linear tail or a stored landmark). Under the free gauge the system is singular and is held for it: by the initial pose
	 * while it is in the problem (every covariance relative to it, the frame swba run reports a free
	 * row in), else by the oldest state and moved to the minimum-norm gauge of the global motions
	 * (the frame hold_gauge keeps). */
	CovarianceResult covariances(CovarianceRequest request);
	/** Block `g` of `r`, a pose's, in the SE(3) tangent (planar rows embedded; NaN when `r` failed). */
	PoseCovariance pose_covariance(const CovarianceResult& r, std::size_t g) const;
	/** Landmarks in the state with the covariance of their world position. */
	std::map<std::int32_t, LandmarkEstimate> landmark_estimates(double* seconds);
	/** @} */

   private:
	/** Fixes the model (Spatial or Planar), the gate's and the loss's χ² bounds for its reading_dof,
	 * and adds the first pose and its gauge. */
	void initialise(PoseModel model);
	/** A new pose variable (planar: projected on the plane). */
	VariableId add_pose_variable(const mrpt::poses::CPose3D& pose);
	/** Adds the odometry factor of `step` between `vprev` and `vnew`; returns its information (6×6 on
	 * the SE(3) tangent, planar: 3×3 on (ρx, ρy, ωz)), which the gate also uses. */
	Eigen::MatrixXd add_odometry_factor(const io::RawlogStep& step, VariableId vprev, VariableId vnew);
	/** The χ² gate step of a reading on arrival (gate_on_entry): a reading of a known landmark enters
	 * or is held; the first reading of a landmark waits for a consistent second one. */
	void admit_reading(std::int32_t id, const Observation& o, StepSummary& sum);
	/** A reading that data association matched to landmark `id` (a graph landmark, or a provisional one
	 * it then confirms): it passed the χ² test of individual compatibility against the window's joint
	 * covariance, so it enters without admit_reading's test (whose odometry-only pose covariance would
	 * hold every reading of a landmark seen again after a long stretch of dead reckoning). */
	void admit_associated(std::int32_t id, const Observation& o);
	/** ReadingGate::distance of reading `o`, taken at pose step o.pose_step, against the world point
	 * `p` (whose estimate averages `n` readings), with the pose at `pose_x` (null: its current value). */
	double innovation_distance(const Eigen::Vector3d& p, std::size_t n, const Observation& o,
							   const Eigen::MatrixXd* pose_cov, const double* pose_x = nullptr) const;
	/** innovation_distance of `o` against landmark `lm`'s current estimate. */
	double gate_distance(const Landmark& lm, const Observation& o, const Eigen::MatrixXd* pose_cov,
						 const double* pose_x = nullptr) const;
	/** Centres the gate (ReadingGate::centre_on) on the newest pose from the `readings` (landmark ID,
	 * reading) of landmarks already in the graph, held at their current estimates. */
	void centre_gate(const std::vector<std::pair<std::int32_t, Observation>>& readings);
	/** Gives every reading of the newest step (`readings`, ID field −1 or ignored) a landmark ID by
	 * data association (association()): the graph's landmarks and the provisional ones (first readings
	 * waiting for confirmation) are predicted in the new pose's sensor frame at its dead-reckoned value,
	 * with their joint covariance from the window's (predict_jointly); an unmatched reading gets a new
	 * ID. */
	void associate_readings(std::vector<std::pair<std::int32_t, Observation>>& readings,
							std::vector<std::int32_t>& assigned, std::vector<bool>& matched);
	/** The joint prediction of `targets` in the sensor frame of pose step k (LandmarkPredictor), with
	 * the joint covariance of the variables it needs from covariances(). */
	JointPrediction predict_jointly(std::size_t k, const std::vector<PredictionTarget>& targets);
	/** The candidates of data association (the graph's landmarks, the provisional ones, the map's) and
	 * their IDs in `ids`, in that order. */
	std::vector<PredictionTarget> association_candidates(std::vector<std::int32_t>& ids) const;
	/** The association's second test (SlidingWindowOptions::association_pose_inflation): the readings
	 * `match` leaves unmatched, against the state's landmarks among `cand` that it left untaken, with
	 * the pose's covariance in `pred` inflated; those it matches get their target in `match`. Returns
	 * how many. */
	std::size_t rematch_with_inflated_pose(const std::vector<std::pair<std::int32_t, Observation>>& readings,
										   const std::vector<PredictionTarget>& cand, const JointPrediction& pred,
										   std::size_t k, ReadingMatch& match) const;
	/** Known IDs: the readings of step k that admit_reading held (its pose covariance is the odometry's
	 * alone) are tested again against the window's joint covariance (predict_jointly); those inside the
	 * gate enter now. After a long stretch without readings the drift is far beyond one step's
	 * odometry covariance: without this, every reading of the landmarks seen again would be held and the
	 * pose would follow the odometry until a solve re-admitted them. Costs a covariance recovery on the
	 * steps that held a reading only. */
	void retest_held(std::size_t k, StepSummary& sum);
	/** World XYZ of landmark `lm` at the current estimate. */
	Eigen::Vector3d world_position(const Landmark& lm) const;
	/** Counts readings the store dropped for good as excluded (and the unconfirmed among them). */
	void count_dropped(const LandmarkStore::Dropped& d);
	/** Adds the factor of `o` to `lm` and records it as admitted. */
	void admit(Landmark& lm, Observation o);
	/** The step's readings (IDs assigned, `matched`: associated to an existing landmark) into the graph:
	 * gated on entry when on, else each joins its landmark (a new one if unknown). */
	void admit_step_readings(const std::vector<std::pair<std::int32_t, Observation>>& readings,
							 const std::vector<bool>& matched, StepSummary& sum);
	/** Adds the landmark of a first reading, initialised from it at pose step k. */
	Landmark& add_landmark(std::int32_t id, const Observation& o);
	/** Map policy: landmark `id` (in the map, not in the state) re-enters as a world point at its map
	 * position with a prior factor of its map covariance; it leaves the map. */
	Landmark& restore_from_map(std::int32_t id);
	/** Requests, for `lms`, the world-position covariance (a world point: its block; inverse depth: the
	 * joint block with its anchor), and turns the result into LandmarkEstimates. */
	std::map<std::int32_t, LandmarkEstimate> estimates_of(const std::vector<const Landmark*>& lms, double* seconds);
	/** ∂(world position of `lm`)/∂(its variable's tangent[, its anchor pose's tangent]): 3 × (tangent of
	 * lm.var) for a world point, 3 × (3 + 6) for inverse depth (λ, then the anchor). */
	Eigen::MatrixXd world_position_jacobian(const Landmark& lm) const;
	/** Builds the factor of observation `o` of landmark `lm` (given its current anchor). */
	FactorId add_observation_factor(const Landmark& lm, const Observation& o);
	/** Moves landmark `lm` onto variable `v` (its new parameterisation, already set in `lm`): removes
	 * its observation factors and old variable, and rebuilds the factors on `v` (an exact rewrite). */
	void replace_landmark_variable(Landmark& lm, VariableId v);

	SlidingWindowOptions opt_;
	PoseModel model_ = PoseModel::Auto;
	smoother::FixedLagSmoother smoother_;
	std::vector<PoseRecord> poses_;
	std::map<VariableId, std::size_t> step_of_;
	LandmarkStore store_;
	mrpt::poses::CPose3D last_sensor_;
	std::shared_ptr<const LossFunction> loss_;  ///< of the reading factors (set with the model)
	double robust_scale_sq_ = 0;                ///< χ²_dof(robust_probability) (set with the model)
	bool gate_on_entry_;
	std::map<double, mrpt::poses::CPose3D> pose_guesses_;
	ReadingGate gate_;  ///< its bound set with the model
	ReadingCounts counts_;
	DataAssociation association_ = DataAssociation::Auto;
	std::int32_t next_landmark_id_ = 0;  ///< the next ID data association gives
	std::vector<std::vector<std::int32_t>> assigned_ids_;
};
}  // namespace swba::estimators::detail
