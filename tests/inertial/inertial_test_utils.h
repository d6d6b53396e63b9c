// Helpers shared by the inertial tests: the estimators' input from a simulated data set and the
// translation error of a trajectory against its truth.
#pragma once

#include <swba/estimators/inertial_filter.h>
#include <swba/problems/inertial_simulation.h>

#include <cmath>

namespace swba::test
{
inline Eigen::Vector3d position(const mrpt::poses::CPose3D& p) { return {p.x(), p.y(), p.z()}; }

/** The simulated pose priors (label MAP) and odometry (label ODO) with the IMU readings. */
inline estimators::InertialInput input_of(const problems::InertialDataset& d)
{
	estimators::InertialInput in;
	in.imu = d.imu;
	for (const auto& z : d.pose_priors) in.pose_priors.push_back({z.t, "MAP", z.pose, z.covariance});
	for (const auto& z : d.odometry) in.odometry.push_back({z.t, "ODO", z.pose, z.covariance});
	return in;
}

/** The truth at time t (the truth is sampled at the IMU rate `rate`). */
inline const problems::InertialTruth& truth_at(const problems::InertialDataset& d, double t, double rate)
{
	return d.truth.at(static_cast<std::size_t>(std::lround(t * rate)));
}

/** Translation RMSE of the trajectory against the truth (report times are IMU times). */
inline double rmse(const estimators::InertialTrajectory& tr, const problems::InertialDataset& d, double rate)
{
	double s = 0;
	for (std::size_t i = 0; i < tr.t.size(); i++)
		s += (position(tr.poses[i]) - position(truth_at(d, tr.t[i], rate).pose)).squaredNorm();
	return std::sqrt(s / static_cast<double>(tr.t.size()));
}
}  // namespace swba::test
