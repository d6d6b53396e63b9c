// What the inertial benchmarks (bench_inertial.cpp, lag_bound.cpp) share: a simulated log with the
// window's options for its noise, and the position error of an estimate against its ground truth.
#pragma once

#include <swba/apps/inertial_simulate.h>
#include <swba/estimators/inertial_window.h>
#include <swba/problems/inertial_simulation.h>

#include <cmath>
#include <cstddef>

namespace swba::bench
{
/** A simulated log as the estimators read it, and the window's options with the simulator's noise
 * (the rest at their defaults). */
struct SimulatedInertialLog
{
	problems::InertialDataset data;
	estimators::InertialInput input;
	estimators::InertialWindowOptions options;
};

inline SimulatedInertialLog simulate_inertial_log(const problems::InertialSimulationOptions& s)
{
	SimulatedInertialLog log;
	log.data = problems::simulate_inertial(s);
	log.input = apps::simulated_inertial_input(log.data);
	log.options.measurements.noise = log.data.noise;
	return log;
}

/** Squared distance (m²) between the position of `pose` and the ground truth's at time t; the truth is
 * sampled at `rate` Hz from t = 0, so t is rounded to its nearest sample. */
inline double squared_position_error(const mrpt::poses::CPose3D& pose, double t, const problems::InertialDataset& d,
									 double rate)
{
	const auto& g = d.truth.at(static_cast<std::size_t>(std::lround(t * rate))).pose;
	return std::pow(pose.x() - g.x(), 2) + std::pow(pose.y() - g.y(), 2) + std::pow(pose.z() - g.z(), 2);
}
}  // namespace swba::bench
