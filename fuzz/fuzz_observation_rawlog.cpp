// Harness: observation-format rawlogs (IMU and robot-pose observations) as `swba run` meets them:
// is_observation_rawlog decides the kind from the first object, then read_observation_rawlog reads the
// file with the default roles and with the simulator's roles (labels resolved, so that mutated
// objects reach the field, timestamp and covariance checks).
#include "fuzz_common.h"

#include <swba/io/observation_rawlog.h>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
	const std::string path = swba::fuzz::write_scratch_file("input.rawlog", swba::fuzz::as_text(data, size));
	swba::io::SensorRoles simulated;
	simulated.imu = {"IMU"};
	simulated.pose_prior = {"MAP_MATCHING"};
	simulated.odometry = {"LIDAR_ODOMETRY"};
	swba::fuzz::read_or_reject([&] { (void)swba::io::is_observation_rawlog(path); });
	for (const auto& roles : {swba::io::SensorRoles{}, simulated})
		swba::fuzz::read_or_reject([&] { (void)swba::io::read_observation_rawlog(path, roles); });
	return 0;
}
