/** \file inertial_window.h
 * The inertial sliding window on the fixed-lag smoother (swba/smoother/fixed_lag_smoother.h): keyframes
 * at the pose-prior times (at the odometry times when there is no prior), each with a PRVAG state —
 * pose T ∈ SE(3) (SE3Manifold), velocity v ∈ ℝ³ (world), biases b = [b_a; b_g] ∈ ℝ⁶ — constrained by an
 * ImuPreintegrationFactor between consecutive keyframes, a PosePriorFactor per pose prior, a
 * BetweenPoseFactor per odometry increment between consecutive keyframes (increments composed when the
 * odometry is faster than the keyframes) and priors on the first velocity (in the body frame under the free
 * gauge) and biases. The oldest keyframe leaves with its velocity and biases in FixedLagSmoother::update
 * (the graph is its client; the (J, e, x₀) prior and first-estimate Jacobians unchanged). After each update, an IMU factor whose b_i moved from
 * its pre-integration's linearisation bias by more than the thresholds is re-integrated and replaced.
 *
 * Gauge: with pose priors the frame is fixed. Without them (IMU + relative poses) x, y, z and yaw are
 * unobservable and roll and pitch are seen through gravity; InertialWindowOptions::gauge says how the four
 * are held (the first keyframe's roll and pitch get the prior odometry_tilt_sigma in every mode). */
#pragma once

#include <swba/core/ini.h>
#include <swba/estimators/inertial_filter.h>
#include <swba/nonlinear/gauge.h>
#include <swba/nonlinear/solver.h>

#include <cstddef>
#include <string>

namespace swba::estimators
{
struct InertialWindowOptions
{
	/** Keyframes in the window (≥ 2); 0 = unbounded (full history, nothing marginalised). (Default = 10) */
	int window_size = 10;
	/** First-estimate Jacobians for the factors touching the marginal prior. (Default = true) */
	bool first_estimate_jacobians = true;
	/** Measurements, noise and initial priors (shared with the filter). */
	InertialFilterOptions measurements;
	/** Re-integrate an IMU factor when |b_a − b̄_a| exceeds this (any axis), m/s². (Default = 0.02) */
	double reintegrate_accel = 0.02;
	/** Re-integrate an IMU factor when |b_g − b̄_g| exceeds this (any axis), rad/s. (Default = 0.002) */
	double reintegrate_gyro = 0.002;
	/** Relative pivot threshold of the marginal prior (FixedLagSmootherOptions). The smoother's 1e-12 is
	 * relative to the largest diagonal of the system, and the bias random-walk rows reach 1/(σ_b² Δt)
	 * ≈ 1e15 for a tactical gyroscope: 1e-12 of that cuts every direction held by less than 1e3 (a pose
	 * prior of σ = 0.5 m holds 4). (Default = 1e-20) */
	double marginalization_threshold = 1e-20;
	/** The four-DoF gauge without pose priors (ignored with them: the priors fix the frame). Prior: the
	 * first keyframe's pose prior from the odometry holds x, y, z, yaw with σ odometry_pose_sigma. Fixed:
	 * they are constant (the first pose moves only in pitch and roll). Free: no information on them (the first
	 * velocity's prior is in the body frame); each solve anchors them on the marginal prior's keyframe at
	 * its first estimate (on the first keyframe before anything is marginalised) and undoes what motion is
	 * left; no covariance is reported (it would be relative to that anchor). (Default = Prior) */
	GaugeMode gauge = GaugeMode::Prior;
	/** Recover the newest pose's marginal covariance after each update. (Default = true) */
	bool covariances = true;
	/** LM options of each update (Default: 10 iterations at most, initial trust region radius 1e12: see
	 * default_solver()). */
	SolverOptions solver = default_solver();

	static SolverOptions default_solver();
	/** Throws std::invalid_argument naming the option. */
	void validate() const;
	/** INI keys: keyframes, gauge, first_estimate_jacobians, reintegrate_accel, reintegrate_gyro (the IMU
	 * noise has its own section: ImuNoise::ini_keys). */
	static IniKeys<InertialWindowOptions> ini_keys(const std::string& section);
};

/** A window run: the online estimate (the newest keyframe after its update), the lagged estimate (each
 * keyframe when it leaves the window, the rest at the end), the cost per keyframe and what was re-integrated. */
struct InertialWindowResult
{
	InertialTrajectory online;
	InertialTrajectory lagged;
	std::vector<double> seconds_per_keyframe;  ///< wall time of each keyframe's update + marginalisation
	std::size_t reintegrations = 0;
	std::size_t relative_factors = 0;
	std::size_t prior_factors = 0;
};

/** Runs the window over the input. Throws std::invalid_argument on invalid options or input. */
InertialWindowResult run_inertial_window(const InertialInput& input, const InertialWindowOptions& options);

/** The same factor graph over all keyframes, solved once at the end (the smoother's batch run). */
InertialTrajectory run_inertial_batch(const InertialInput& input, const InertialWindowOptions& options);
}  // namespace swba::estimators
