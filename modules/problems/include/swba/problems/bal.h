/** \file bal.h
 * A BAL problem (swba/io/bal.h) as a swba::Problem: one Euclidean(9) variable per camera (Kept),
 * one Euclidean(3) variable per point (Eliminable, removed by the Schur complement), one
 * SnavelyReprojectionFactor per observation; and what the Snavely camera model says about the
 * values (points behind their camera, camera centres, the PLY view of cameras and points). */
#pragma once

#include <swba/core/loss.h>
#include <swba/io/bal.h>
#include <swba/nonlinear/problem.h>

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

namespace swba::problems
{
/** The variables created for a BAL problem in a swba::Problem. */
struct BalVariables
{
	std::vector<VariableId> cameras;  ///< Euclidean(9), Group::Kept
	std::vector<VariableId> points;   ///< Euclidean(3), Group::Eliminable
	int num_unobserved_cameras = 0;   ///< set constant (they have no factor)
	int num_unobserved_points = 0;    ///< set constant (they have no factor)
};

/** Adds one variable per camera and point and one SnavelyReprojectionFactor per observation (with
 * `loss`, null = plain least squares). Cameras/points without observations are set constant. */
BalVariables add_bal_to_problem(const io::BalProblem& bal, Problem& problem,
								std::shared_ptr<const LossFunction> loss = nullptr);

/** Copies the variables' current values back into `bal`. */
void copy_values_to_bal(const Problem& problem, const BalVariables& vars, io::BalProblem& bal);

/** Number of observations whose point lies behind its camera (P.z ≥ 0 in the camera frame; the
 * Snavely cameras look along −z). */
int count_observations_behind_camera(const io::BalProblem& problem);

/** Camera centres −R(ω)ᵀt, in camera order. */
std::vector<Eigen::Vector3d> bal_camera_centres(const io::BalProblem& problem);

/** PLY with the camera centres (green) followed by the points (white). */
void write_bal_ply(const std::string& path, const io::BalProblem& problem);
}  // namespace swba::problems
