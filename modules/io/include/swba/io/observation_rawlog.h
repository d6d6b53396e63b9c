/** \file observation_rawlog.h
 * Observation-format MRPT rawlogs ("format #2": a stream of timestamped CObservation objects of any
 * sensors) with IMU readings (mrpt::obs::CObservationIMU) and poses (mrpt::obs::CObservationRobotPose),
 * read into plain records; a sensor's role (IMU, global pose prior, odometry) is chosen by its label
 * (SensorRoles, INI section [sensors]). The schema is doc/rawlogs.md, "Inertial rawlogs".
 *
 * Frames: the estimator's body frame is the IMU's frame. Each observation's sensorPose is the sensor on
 * the vehicle; a pose measured by a sensor S is converted to the IMU frame with C = S⁻¹·I (S, I the
 * sensor poses of the pose sensor and of the IMU): T_world_imu = T_world_S·C, an odometry increment
 * D ↦ C⁻¹·D·C, and their covariances with the adjoint of C. */
#pragma once

#include <swba/core/ini.h>

#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <mrpt/poses/CPose3D.h>

#include <Eigen/Core>
#include <cstddef>
#include <string>
#include <vector>

namespace swba::io
{
/** Which sensor label plays which role. A label list is comma-separated, spaces ignored. */
struct SensorRoles
{
	/** Labels of the IMU to use; empty = every CObservationIMU (they must then share one label).
	 * (Default = "") */
	std::vector<std::string> imu;
	/** Labels of CObservationRobotPose used as global pose priors; empty = every label not in
	 * `odometry`. (Default = "") */
	std::vector<std::string> pose_prior;
	/** Labels of CObservationRobotPose read as consecutive poses of a drifting odometry (e.g. lidar
	 * odometry): only the relative motion between consecutive poses of the label is used. (Default = "") */
	std::vector<std::string> odometry;

	/** Throws std::invalid_argument naming a label that is in both pose_prior and odometry. */
	void validate() const;
	/** Keys imu, pose_prior, odometry in `section` (e.g. "sensors"). */
	static IniKeys<SensorRoles> ini_keys(const std::string& section);
};

/** One IMU reading, in the IMU frame: t in seconds from the rawlog's first observation. */
struct ImuReading
{
	double t = 0;
	Eigen::Vector3d acc = Eigen::Vector3d::Zero();	 ///< specific force, m/s² (IMU_X_ACC, IMU_Y_ACC, IMU_Z_ACC)
	Eigen::Vector3d gyro = Eigen::Vector3d::Zero();	 ///< angular rate, rad/s (IMU_WX, IMU_WY, IMU_WZ)
};

/** A pose of the IMU frame (prior: in the world; odometry: in the odometry's frame) with its covariance
 * in the local tangent [ρ, ω] (right perturbation, as SE3Manifold). */
struct PoseReading
{
	double t = 0;
	std::string label;
	mrpt::poses::CPose3D pose;
	Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
};

struct ObservationRawlog
{
	std::string path;
	double time_origin = 0;	 ///< MRPT time (Unix seconds) of the first observation: t = 0
	std::vector<ImuReading> imu;
	std::vector<PoseReading> pose_priors;
	/** Every odometry pose in time order (its covariance: of the increment since the previous pose of
	 * the same label, in that previous pose's tangent). */
	std::vector<PoseReading> odometry;
	std::size_t entries = 0;		  ///< objects read
	std::size_t ignored_entries = 0;  ///< other classes, or labels with no role
	std::vector<std::string> warnings;  ///< e.g. bytes after the last gzip member, ignored
};

/** True when the file's first object is a bare CObservation (an observation-format rawlog); false for
 * an action/sensory-frame rawlog. Throws std::runtime_error naming the file when it cannot be read. */
bool is_observation_rawlog(const std::string& path);

/** Reads an observation-format rawlog. Throws std::runtime_error naming the file and the entry on an
 * unreadable file, a gzip stream that ends inside a member (even on an object boundary), an IMU
 * observation lacking any of the six fields, decreasing timestamps of one sensor, a covariance that
 * is not symmetric positive semi-definite, or invalid roles. */
ObservationRawlog read_observation_rawlog(const std::string& path, const SensorRoles& roles = {});

/** A CObservationIMU at MRPT time `origin + t` (100 ns ticks) with the six fields set by name. */
mrpt::obs::CObservationIMU::Ptr make_imu_observation(double origin, double t, const Eigen::Vector3d& acc,
													 const Eigen::Vector3d& gyro, const std::string& label);
/** A CObservationRobotPose at MRPT time `origin + t` with covariance `ypr_covariance` (MRPT's
 * x y z yaw pitch roll order). */
mrpt::obs::CObservationRobotPose::Ptr make_pose_observation(double origin, double t, const mrpt::poses::CPose3D& pose,
															const Eigen::Matrix<double, 6, 6>& ypr_covariance,
															const std::string& label);
/** The covariance in MRPT's (x, y, z, yaw, pitch, roll) parameters of a pose `at` whose covariance in
 * the local tangent is `tangent_covariance`: J⁻¹ Σ J⁻ᵀ with J = ypr_to_tangent_jacobian(at). */
Eigen::Matrix<double, 6, 6> ypr_covariance_from_tangent(const mrpt::poses::CPose3D& at,
														const Eigen::Matrix<double, 6, 6>& tangent_covariance);
/** Writes the objects in order to a gzip-compressed rawlog (concatenated gzip members of about 8 MiB of
 * objects each), through write_file_atomically: throws std::runtime_error "cannot write '<path>': <OS
 * reason>". */
void write_observation_rawlog(const std::string& path, const std::vector<mrpt::obs::CObservation::Ptr>& objects);

/** The adjoint map of a constant right factor C: for Z·PseudoExp(δ)·C = (Z·C)·PseudoExp(A·δ) to first
 * order, A = [[R_Cᵀ, −R_Cᵀ[t_C]×], [0, R_Cᵀ]]. */
Eigen::Matrix<double, 6, 6> right_factor_adjoint(const mrpt::poses::CPose3D& C);
}  // namespace swba::io
