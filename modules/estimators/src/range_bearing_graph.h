/** \file range_bearing_graph.h
 * (private to the estimators module) Range-bearing SLAM as a factor graph on a fixed-lag smoother: one
 * SE(3) pose per step (odometry between consecutive poses, the first pose gauge-fixed as the options
 * say), one landmark variable per landmark ID (inverse depth in its anchor's sensor frame, or world
 * XYZ), one range-bearing factor per reading. The window (SlidingWindowEstimator) and the batch run
 * (run_batch) are both built on it. */
#pragma once

#include <swba/estimators/sliding_window.h>
#include <swba/factors/range_bearing.h>
#include <swba/smoother/fixed_lag_smoother.h>

#include <cstddef>
#include <cstdint>
#include <map>
#include <set>
#include <vector>

namespace swba::estimators::detail
{
struct Observation
{
	std::size_t pose_step;  ///< index into poses() (0 = initial pose)
	RangeBearingMeasurement z;
	Eigen::Vector3d sigma;
	FactorId factor = -1;
};

struct Landmark
{
	std::int32_t id;
	VariableId var;
	std::size_t anchor_step = 0;  ///< inverse depth only
	/** Inverse-depth mode: the landmark was in the marginal prior when its anchor left the window, so it
	 * was switched to world XYZ (a parameterisation no later marginalisation has to change). */
	bool world_xyz = false;
	std::vector<Observation> obs;  ///< observations whose factors are still in the problem
};

struct PoseRecord
{
	double time;
	VariableId var;
	mrpt::poses::CPose3D sensor;  ///< sensor pose on the robot at this step
};

class RangeBearingGraph
{
   public:
	/** Validates `options` (throws std::invalid_argument) and adds the first pose at the origin (time 0)
	 * as the first state, constant or with a pose prior as options.gauge says. */
	explicit RangeBearingGraph(const SlidingWindowOptions& options);

	const SlidingWindowOptions& options() const { return opt_; }
	smoother::FixedLagSmoother& smoother() { return smoother_; }
	const smoother::FixedLagSmoother& smoother() const { return smoother_; }

	/** Adds the step's pose (dead reckoning from the newest pose), its odometry factor and one factor
	 * per reading (a new landmark initialised from its first reading); counts readings in `sum`.
	 * Throws std::invalid_argument on a step without odometry or with a non-positive sensor noise. */
	void add_step(const io::RawlogStep& step, StepSummary& sum);

	/** Every pose ever created, by step (0 = initial). */
	const std::vector<PoseRecord>& poses() const { return poses_; }
	/** Step of the pose variable `var`. */
	std::size_t step_of(VariableId pose_var) const { return step_of_.at(pose_var); }
	std::map<std::int32_t, Landmark>& landmarks() { return landmarks_; }
	const std::map<std::int32_t, Landmark>& landmarks() const { return landmarks_; }
	bool is_landmark(VariableId v) const { return landmark_of_var_.count(v) > 0; }
	/** A landmark variable holding a world point (XYZ parameterisation, or switched to world XYZ). */
	bool is_world_point(VariableId v) const;
	/** World XYZ of every landmark by ID. */
	std::map<std::int32_t, Eigen::Vector3d> landmark_positions() const;

	/** Forgets the landmark of variable `v` (being marginalised); false when `v` is no landmark. */
	bool forget_landmark(VariableId v);
	/** Drops the observations whose factors are in `removed`. */
	void forget_observations(const std::set<FactorId>& removed);

	/** Re-anchors inverse-depth landmark `lm` to pose step `b`: an exact rewrite of its factors, and a
	 * first-order change of variables λ = g(T_a, T_b, λ') in the prior if λ is in it. */
	void reanchor(Landmark& lm, std::size_t b);
	/** Switches inverse-depth landmark `lm`, which is in the marginal prior and whose anchor a is about
	 * to be marginalised, to world XYZ p: an exact rewrite of its factors, and a first-order change of
	 * variables λ = g(T_a, p) (p seen from a's sensor, as inverse depth) in the prior, at the first
	 * estimates. T_a is marginalised right after, so the prior never depends on a re-anchoring again:
	 * a landmark in the prior changes parameterisation once, not every time its anchor leaves. */
	void convert_to_world_xyz(Landmark& lm);

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

   private:
	/** Adds the landmark of a first reading, initialised from it at pose step k. */
	Landmark& add_landmark(std::int32_t id, const Observation& o);
	/** Builds the factor of observation `o` of landmark `lm` (given its current anchor). */
	FactorId add_observation_factor(const Landmark& lm, const Observation& o);
	/** Moves landmark `lm` onto variable `v` (its new parameterisation, already set in `lm`): removes
	 * its observation factors and old variable, and rebuilds the factors on `v` (an exact rewrite). */
	void replace_landmark_variable(Landmark& lm, VariableId v);

	SlidingWindowOptions opt_;
	smoother::FixedLagSmoother smoother_;
	std::vector<PoseRecord> poses_;
	std::map<VariableId, std::size_t> step_of_;
	std::map<std::int32_t, Landmark> landmarks_;
	std::map<VariableId, std::int32_t> landmark_of_var_;
	mrpt::poses::CPose3D last_sensor_;
};
}  // namespace swba::estimators::detail
