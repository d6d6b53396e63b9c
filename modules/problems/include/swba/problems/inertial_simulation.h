/** \file inertial_simulation.h
 * Simulated inertial data sets with exact ground truth: an analytic trajectory (a 3-D figure-eight with
 * vertical oscillation and changing attitude, or a planar car-like drive with turns and stops), the IMU
 * readings it produces (specific force f = Rᵀ(p̈ − g), body rate from the attitude's derivative, plus
 * white noise and random-walk biases of an IMU grade), global pose priors and a drifting odometry.
 * Deterministic per seed. Conventions as swba/factors/imu_preintegration.h (z up, gravity −9.81 z). */
#pragma once

#include <swba/core/names.h>
#include <swba/factors/imu_preintegration.h>

#include <mrpt/poses/CPose3D.h>

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace swba::problems
{
enum class InertialTrajectoryKind
{
	FigureEight,  ///< "figure8": 3-D figure-eight, z oscillating, heading along the path, rolling and pitching
	Car			  ///< "car": planar figure-eight drive, heading along the path, slowing to stops
};
constexpr std::array<EnumName<InertialTrajectoryKind>, 2> enum_names(InertialTrajectoryKind)
{
	return {{{InertialTrajectoryKind::FigureEight, "figure8"}, {InertialTrajectoryKind::Car, "car"}}};
}

enum class ImuGrade
{
	Consumer,  ///< "consumer": MEMS (σ_a 0.019 m/s²/√Hz, σ_g 0.015 rad/s/√Hz, walks 1e-4 / 1e-5)
	Tactical   ///< "tactical": σ_a 1e-3, σ_g 1.5e-5 (0.05°/√h), walks 1e-5 / 1e-7
};
constexpr std::array<EnumName<ImuGrade>, 2> enum_names(ImuGrade)
{
	return {{{ImuGrade::Consumer, "consumer"}, {ImuGrade::Tactical, "tactical"}}};
}

/** Noise densities of a grade, and the standard deviations of its initial biases (accelerometer m/s²,
 * gyroscope rad/s: consumer 0.05 / 0.005, tactical 0.01 / 5e-6). */
ImuNoise imu_grade_noise(ImuGrade grade);
Eigen::Vector2d imu_grade_initial_bias_sigma(ImuGrade grade);

/** The exact kinematics of the body at one time. */
struct Kinematics
{
	Eigen::Matrix3d R;		 ///< body → world
	Eigen::Vector3d p, v, a;  ///< world position, velocity, acceleration p̈
	Eigen::Vector3d omega;	 ///< body angular rate (Rᵀ Ṙ = [ω]×)
};

/** Kinematics of the analytic trajectory at time t (s). */
Kinematics trajectory_kinematics(InertialTrajectoryKind kind, double t);

/** The exact (noise-free, bias-free) IMU reading at time t. */
ImuSample exact_imu(InertialTrajectoryKind kind, double t, const Eigen::Vector3d& gravity);

struct InertialSimulationOptions
{
	InertialTrajectoryKind trajectory = InertialTrajectoryKind::FigureEight;  ///< (Default = figure8)
	ImuGrade grade = ImuGrade::Consumer;  ///< (Default = consumer)
	double duration = 60;  ///< seconds (Default = 60)
	double imu_rate = 100;	///< Hz (Default = 100)
	double pose_rate = 10;	///< global pose priors, Hz, dividing imu_rate (Default = 10); 0 = none
	double odometry_rate = 10;	 ///< odometry poses, Hz, dividing imu_rate (Default = 10); 0 = none
	double pose_sigma_m = 0.5;	 ///< pose prior σ per axis, metres (Default = 0.5)
	double pose_sigma_rad = 0.017453292519943295;  ///< pose prior σ per axis, radians (Default = 1°)
	/** Odometry noise per step: σ of each translation axis as a fraction of the step's length
	 * (Default = 0.01, "1 % drift"), with a floor of 1 mm. */
	double odometry_drift = 0.01;
	/** Odometry rotation noise per step, radians per radian turned, with a floor of 1e-4 rad (Default = 0.01). */
	double odometry_rotation_drift = 0.01;
	/** No IMU noise, no bias, no pose or odometry noise (Default = false). */
	bool noise_free = false;
	std::uint64_t seed = 1;  ///< (Default = 1)

	/** Throws std::invalid_argument naming the option. */
	void validate() const;
};

/** A pose measurement with its covariance in the local tangent [ρ, ω] of the pose (right perturbation). */
struct TimedPoseMeasurement
{
	double t = 0;
	mrpt::poses::CPose3D pose;
	Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Identity();
};

/** The true state at one IMU time. */
struct InertialTruth
{
	double t = 0;
	mrpt::poses::CPose3D pose;
	Eigen::Vector3d v = Eigen::Vector3d::Zero();
	Vector6d bias = Vector6d::Zero();
};

struct InertialDataset
{
	ImuNoise noise;						   ///< the IMU's noise model (the grade's; gravity −9.81 z)
	std::vector<ImuSample> imu;			   ///< readings at imu_rate from t = 0
	std::vector<TimedPoseMeasurement> pose_priors;
	/** Odometry poses in the odometry's own frame (equal to the world at t = 0); covariance: of the
	 * increment since the previous odometry pose, in the previous pose's tangent. */
	std::vector<TimedPoseMeasurement> odometry;
	std::vector<InertialTruth> truth;	   ///< at every IMU reading
};

/** Simulates a data set. Throws std::invalid_argument on invalid options. */
InertialDataset simulate_inertial(const InertialSimulationOptions& options);
}  // namespace swba::problems
