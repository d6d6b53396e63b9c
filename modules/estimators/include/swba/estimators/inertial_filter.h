/** \file inertial_filter.h
 * Inertial estimation inputs and the baseline filter: a 15-state error-state Kalman filter (ESKF) driven
 * by the IMU with the same midpoint propagation as the pre-integration (swba/factors/imu_preintegration.h),
 * updated by global pose priors and by relative poses of a drifting odometry (through a stochastic clone
 * of the pose at the previous odometry time).
 *
 * Error state δx = [δp, δφ, δv, δb_a, δb_g]: p_true = p + δp and v_true = v + δv (world), R_true = R·Exp(δφ)
 * (right, local attitude error), b_true = b + δb. A pose measurement Z with covariance Σ in its local tangent
 * has the residual of swba::PosePriorFactor, r = PseudoLog(Z⁻¹·T); an odometry increment D that of
 * swba::BetweenPoseFactor between the clone and the current pose; the filter takes their Jacobians from those
 * factors (converted from the SE(3) manifold's [ρ (body), ω] to [δp (world), δφ]). */
#pragma once

#include <swba/core/names.h>
#include <swba/factors/imu_preintegration.h>
#include <swba/io/observation_rawlog.h>

#include <mrpt/poses/CPose3D.h>

#include <Eigen/Core>
#include <array>
#include <optional>
#include <vector>

namespace swba::estimators
{
using Matrix6d = Eigen::Matrix<double, 6, 6>;

/** What an inertial estimator is given: IMU readings in time order and pose readings in the IMU frame. */
struct InertialInput
{
	std::vector<ImuSample> imu;
	std::vector<io::PoseReading> pose_priors;
	std::vector<io::PoseReading> odometry;
};

/** The IMU readings of an observation rawlog as ImuSample (same fields). */
InertialInput inertial_input(const io::ObservationRawlog& log);

/** The input with every reading after time t dropped (what an estimator has seen at t). */
InertialInput inertial_input_until(const InertialInput& input, double t);

/** Priors on the first state: its pose from the first pose prior (else the first odometry pose: the
 * odometry's frame is then the world up to a tilt, see odometry_tilt_sigma), its velocity from the first
 * odometry increment (else zero) and zero biases. */
struct InertialPriorOptions
{
	/** σ of the initial velocity per axis, m/s, when it comes from odometry (Default = 0.2). */
	double velocity_sigma = 0.2;
	/** σ of the initial velocity per axis, m/s, when there is no odometry to take it from (Default = 5). */
	double velocity_sigma_unknown = 5.0;
	/** σ of the initial accelerometer bias per axis, m/s² (Default = 0.1). */
	double accel_bias_sigma = 0.1;
	/** σ of the initial gyroscope bias per axis, rad/s (Default = 0.01). */
	double gyro_bias_sigma = 0.01;
	/** Without pose priors the frame is free along x, y, z and yaw (the gauge of IMU + relative poses):
	 * the initial pose from the odometry holds those four with this σ (m and rad, Default = 1e-3)... */
	double odometry_pose_sigma = 1e-3;
	/** ...and its roll and pitch (rotations about the world's x and y axes) only with this σ, rad: gravity
	 * observes them, so an odometry frame that is not level is corrected (Default = 0.1). */
	double odometry_tilt_sigma = 0.1;

	/** Throws std::invalid_argument naming the option that is out of range. */
	void validate() const;
};

/** The initial state and its 15×15 covariance (order [p, φ, v, b_a, b_g]). */
struct InertialInitialState
{
	double t = 0;
	NavState x;
	Vector6d bias = Vector6d::Zero();
	Eigen::Matrix<double, 15, 15> P = Eigen::Matrix<double, 15, 15>::Identity();
};

/** Throws std::invalid_argument when the input has no IMU reading or no pose to start from. */
InertialInitialState initial_inertial_state(const InertialInput& input, const InertialPriorOptions& options);

/** The 15-state ESKF (see the file comment). */
class ErrorStateKalmanFilter
{
   public:
	ErrorStateKalmanFilter(const ImuNoise& noise, const InertialInitialState& initial);

	/** Midpoint propagation from reading s0 to s1 (s0.t must be the filter's time). */
	void propagate(const ImuSample& s0, const ImuSample& s1);
	/** Update with a global pose Z of tangent covariance Σ. Returns the normalised innovation squared. */
	double update_pose(const mrpt::poses::CPose3D& Z, const Matrix6d& covariance);
	/** Clones the current pose: the next update_relative() measures the motion from here. */
	void clone_pose();
	bool has_clone() const { return clone_.has_value(); }
	/** Update with the increment D (pose now in the frame of the clone) of tangent covariance Σ, then
	 * drops the clone. Throws std::logic_error without a clone. */
	double update_relative(const mrpt::poses::CPose3D& D, const Matrix6d& covariance);

	double time() const { return t_; }
	const NavState& state() const { return x_; }
	const Vector6d& bias() const { return b_; }
	mrpt::poses::CPose3D pose() const;
	/** Covariance of [δp, δφ, δv, δb_a, δb_g]. */
	Eigen::Matrix<double, 15, 15> covariance() const { return P_.topLeftCorner<15, 15>(); }
	/** Covariance of the pose in the SE(3) manifold's tangent [ρ (body), ω], as the window reports it. */
	Matrix6d pose_covariance() const;

   private:
	/** Kalman update of the residual r with Jacobian H (over the state, clone included). */
	double update(const Eigen::Matrix<double, 6, 1>& r, const Eigen::MatrixXd& H, const Matrix6d& covariance);
	void inject(const Eigen::VectorXd& dx);

	ImuNoise noise_;
	double t_ = 0;
	NavState x_;
	Vector6d b_;
	Eigen::MatrixXd P_;  ///< 15×15, or 21×21 with the clone's [δp, δφ] last
	struct Clone
	{
		Eigen::Matrix3d R;
		Eigen::Vector3d p;
	};
	std::optional<Clone> clone_;
};

/** Where the window's keyframes are, and so where every inertial row reports its estimate. */
enum class KeyframeTimes
{
	/** At the pose-prior times (the odometry times without priors): the odometry increments between two
	 * keyframes are composed into one relative pose, and a window of W keyframes spans W prior periods. */
	PosePriors,
	/** At every pose reading (pose priors and odometry poses): nothing is composed, so the online window is
	 * the filter's estimate; a window of W keyframes spans fewer seconds when the odometry is faster. */
	PoseReadings
};

constexpr std::array<EnumName<KeyframeTimes>, 2> enum_names(KeyframeTimes)
{
	return {{{KeyframeTimes::PosePriors, "priors"}, {KeyframeTimes::PoseReadings, "poses"}}};
}

/** Which measurements a filter run uses, and where it reports. */
struct InertialFilterOptions
{
	ImuNoise noise;
	InertialPriorOptions prior;
	bool use_pose_priors = true;  ///< (Default = true)
	bool use_odometry = true;	  ///< (Default = true)
	KeyframeTimes keyframes = KeyframeTimes::PosePriors;  ///< (Default = PosePriors)
};

/** The filter's estimate after each report time (inertial_report_times), and the filter's cost. */
struct InertialTrajectory
{
	std::vector<double> t;
	std::vector<mrpt::poses::CPose3D> poses;
	std::vector<Eigen::Vector3d> velocities;
	std::vector<Vector6d> biases;
	std::vector<Matrix6d> pose_covariances;	 ///< in the SE(3) tangent [ρ, ω]
	std::size_t imu_steps = 0;
};

/** Report times of an input: its pose-prior times, or its odometry times when it has no prior; with
 * KeyframeTimes::PoseReadings the odometry times too (merged in time order; readings within 1 µs are one time). */
std::vector<double> inertial_report_times(const InertialInput& input, KeyframeTimes keyframes);

/** Runs the ESKF over the whole input (IMU-only dead reckoning with both updates off). */
InertialTrajectory run_inertial_filter(const InertialInput& input, const InertialFilterOptions& options);

/** Odometry-only dead reckoning: the odometry's increments chained from the initial pose, reported at
 * `report_times` (the latest odometry pose at or before each). */
InertialTrajectory run_odometry_dead_reckoning(const InertialInput& input, const InertialPriorOptions& prior,
											  const std::vector<double>& report_times);
}  // namespace swba::estimators
