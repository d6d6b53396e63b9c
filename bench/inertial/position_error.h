// The position error of an inertial estimate against the simulator's ground truth, shared by the
// inertial benchmarks (bench_inertial.cpp, lag_bound.cpp).
#pragma once

#include <swba/estimators/inertial_filter.h>
#include <swba/problems/inertial_simulation.h>

#include <cmath>
#include <cstddef>

namespace swba::bench
{
/** Squared distance (m²) between the position of `pose` and the ground truth's at time t; the truth is
 * sampled at `rate` Hz from t = 0, so t is rounded to its nearest sample. */
inline double squared_position_error(const mrpt::poses::CPose3D& pose, double t, const problems::InertialDataset& d,
									 double rate)
{
	const auto& g = d.truth.at(static_cast<std::size_t>(std::lround(t * rate))).pose;
	return std::pow(pose.x() - g.x(), 2) + std::pow(pose.y() - g.y(), 2) + std::pow(pose.z() - g.z(), 2);
}
}  // namespace swba::bench
