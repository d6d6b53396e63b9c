// The inertial benchmarks' input: a simulated data set as the estimators read it.
#pragma once

#include <swba/estimators/inertial_filter.h>
#include <swba/problems/inertial_simulation.h>

namespace swba::bench
{
/** The simulated pose priors (label MAP) and odometry (label ODO) with the IMU readings. */
inline estimators::InertialInput input_of(const problems::InertialDataset& d)
{
	estimators::InertialInput in;
	in.imu = d.imu;
	for (const auto& z : d.pose_priors) in.pose_priors.push_back({z.t, "MAP", z.pose, z.covariance});
	for (const auto& z : d.odometry) in.odometry.push_back({z.t, "ODO", z.pose, z.covariance});
	return in;
}
}  // namespace swba::bench
