/** \file inertial_simulate.h
 * `swba simulate-imu`: an inertial observation-format rawlog (IMU, map-matching pose priors, lidar-like
 * odometry) with exact ground truth, from swba::problems::simulate_inertial. */
#pragma once

#include <swba/estimators/inertial_filter.h>
#include <swba/problems/inertial_simulation.h>

#include <iosfwd>
#include <string>

namespace swba::apps
{
struct InertialSimulateOptions
{
	problems::InertialSimulationOptions simulation;
	/** Output directory, created. (Default = ".") */
	std::string out_dir = ".";
	/** Base name of the outputs; "" = <trajectory>_<grade>_seed<seed>. (Default = "") */
	std::string name;

	/** Throws std::invalid_argument naming the option. */
	void validate() const;
	std::string output_name() const;
};

/** Sensor labels the simulator writes. */
inline const char* const kSimulatedImuLabel = "IMU";
inline const char* const kSimulatedPosePriorLabel = "MAP_MATCHING";
inline const char* const kSimulatedOdometryLabel = "LIDAR_ODOMETRY";

/** What simulate_inertial_rawlog wrote. */
struct SimulatedInertialRawlog
{
	std::string rawlog;		   ///< <out>/<name>.rawlog: CObservationIMU + CObservationRobotPose, time order
	std::string ground_truth;  ///< <out>/<name>_ground_truth.tum: TUM, every IMU time (seconds from the first)
	/** <out>/<name>_ground_truth_robot_path.txt: MRPT's x y z yaw pitch roll, one row per pose prior
	 * (per IMU reading when there are none). */
	std::string robot_path;
	/** <out>/<name>_ground_truth_state.txt: t, x y z qx qy qz qw, v (world), b_a, b_g at every IMU time. */
	std::string state;
	/** <out>/<name>.ini: the [sensors] roles and the [imu] noise of the simulated grade. */
	std::string ini;
};

/** The simulated data set as the estimators read it from the rawlog simulate_inertial_rawlog writes (the
 * same readings and covariances, the labels above), without the file. */
estimators::InertialInput simulated_inertial_input(const problems::InertialDataset& data);

/** Simulates, writes the files and a line on `log`. Throws std::invalid_argument on invalid options,
 * std::runtime_error naming a file that cannot be written. */
SimulatedInertialRawlog simulate_inertial_rawlog(const InertialSimulateOptions& options, std::ostream& log);
}  // namespace swba::apps
