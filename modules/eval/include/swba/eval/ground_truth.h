/** \file ground_truth.h
 * MRPT's simulated ground truth (`*_ground_truth_robot_path.txt`) paired with an estimator's output.
 * Row i is the true pose when sensory frame SF_i was taken; rawlog step k (odometry AC_k, observations
 * SF_{k+1}) yields the estimate at time t = k + 1, which pairs with row k + 1. */
#pragma once

#include <swba/eval/metrics.h>
#include <swba/eval/trajectory.h>

#include <mrpt/poses/CPose3D.h>

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace swba::eval
{
/** `<dir>/<name>_ground_truth_robot_path.txt` for `<dir>/<name>.rawlog` (mrpt-common's naming). */
std::string default_ground_truth_path(const std::string& rawlog_path);
/** `<dir>/<name>_ground_truth.txt` for `<dir>/<name>.rawlog`: the simulator's landmark file (mrpt-common's
 * and simul-landmarks' naming; estimators::read_landmark_ground_truth reads it). */
std::string default_landmarks_path(const std::string& rawlog_path);

/** Reads the ground truth and checks it has at least steps + 1 rows (row k + 1 pairs with the estimate
 * after step k): MRPT's robot path (x y z yaw pitch roll), or a TUM trajectory (t x y z qx qy qz qw;
 * a file named *.tum or whose first data line has 8 columns), also taken row by row, its stamps not
 * used (swba run's gt.tum, t = row, reads back as the same rows). Throws std::runtime_error naming
 * the file. */
std::vector<mrpt::poses::CPose3D> read_ground_truth_for(const std::string& path, std::size_t steps);

/** The ground truth as a TUM trajectory: row i at t = i. */
Trajectory ground_truth_trajectory(const std::vector<mrpt::poses::CPose3D>& rows);

/** The reference paired with `estimate` pose by pose: for the estimate at t = k + 1, GT row k + 1.
 * Throws std::runtime_error when a stamp is not a whole number ≥ 1 or its row does not exist. */
Trajectory paired_ground_truth(const std::vector<mrpt::poses::CPose3D>& rows, const Trajectory& estimate);

/** APE per pose (not aligned) of `estimate` against the paired ground truth, one per estimate pose. */
std::vector<double> ape_errors_against_ground_truth(const std::vector<mrpt::poses::CPose3D>& rows,
													 const Trajectory& estimate, PoseRelation relation);

/** APE (not aligned) of `estimate` against the paired ground truth: {translation part, full transformation}. */
std::pair<Statistics, Statistics> ape_against_ground_truth(
	const std::vector<mrpt::poses::CPose3D>& rows, const Trajectory& estimate);
}  // namespace swba::eval
