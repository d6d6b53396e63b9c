// Helpers shared by the inertial tests: the estimators' input from a simulated data set and the
// translation error of a trajectory against its truth.
#pragma once

#include <swba/apps/inertial_simulate.h>
#include <swba/core/chi2.h>
#include <swba/estimators/inertial_filter.h>
#include <swba/problems/inertial_simulation.h>

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <vector>

namespace swba::test
{
inline Eigen::Vector3d position(const mrpt::poses::CPose3D& p) { return {p.x(), p.y(), p.z()}; }

/** The estimators' input of a simulated data set. */
inline constexpr auto input_of = &apps::simulated_inertial_input;

/** The truth at time t (the truth is sampled at the IMU rate `rate`). */
inline const problems::InertialTruth& truth_at(const problems::InertialDataset& d, double t, double rate)
{
	return d.truth.at(static_cast<std::size_t>(std::lround(t * rate)));
}

/** Angle between the true and the estimated gravity direction in the body frame (roll and pitch error). */
inline double tilt_error(const mrpt::poses::CPose3D& est, const mrpt::poses::CPose3D& truth)
{
	const Eigen::Vector3d z(0, 0, 1);
	const Eigen::Vector3d a = est.getRotationMatrix().asEigen().transpose() * z,
						  b = truth.getRotationMatrix().asEigen().transpose() * z;
	return std::acos(std::clamp(a.dot(b), -1.0, 1.0));
}

/** Translation RMSE of the trajectory against the truth (report times are IMU times). */
inline double rmse(const estimators::InertialTrajectory& tr, const problems::InertialDataset& d, double rate)
{
	double s = 0;
	for (std::size_t i = 0; i < tr.t.size(); i++)
		s += (position(tr.poses[i]) - position(truth_at(d, tr.t[i], rate).pose)).squaredNorm();
	return std::sqrt(s / static_cast<double>(tr.t.size()));
}
/** Adds each report time's position NEES of `tr` against the truth (error and covariance in the body
 * frame) to `sum` (sized on the first call). */
inline void add_position_nees(std::vector<double>& sum, const estimators::InertialTrajectory& tr,
							  const problems::InertialDataset& d, double rate)
{
	if (sum.empty()) sum.assign(tr.t.size(), 0.0);
	for (std::size_t i = 0; i < tr.t.size(); i++)
	{
		const Eigen::Vector3d e = position(truth_at(d, tr.t[i], rate).pose - tr.poses[i]);
		sum[i] += e.dot(tr.pose_covariances[i].topLeftCorner<3, 3>().ldlt().solve(e));
	}
}

/** The average over `runs` of the summed NEES: its mean, the two-sided 95 % band of the average of `runs`
 * χ²(3) variables, and the share of report times inside it. */
struct NeesBand
{
	double mean = 0, lo = 0, hi = 0, inside = 0;
};
inline NeesBand nees_band(const std::vector<double>& sum, int runs)
{
	NeesBand b;
	b.lo = chi2_quantile(0.025, 3 * runs) / runs;
	b.hi = chi2_quantile(0.975, 3 * runs) / runs;
	int inside = 0;
	for (double x : sum)
	{
		inside += (x / runs >= b.lo && x / runs <= b.hi);
		b.mean += x / runs / static_cast<double>(sum.size());
	}
	b.inside = double(inside) / static_cast<double>(sum.size());
	return b;
}
}  // namespace swba::test
