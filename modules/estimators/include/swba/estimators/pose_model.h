/** \file pose_model.h
 * Which robot the estimators model: a 6D robot (SE(3) poses, 3D landmarks, range-yaw-pitch readings)
 * or a planar one (SE(2) poses, landmarks on the sensor's plane, range-yaw readings), and how the
 * choice is made from the data. */
#pragma once

#include <swba/core/names.h>
#include <swba/io/rawlog.h>

#include <Eigen/Core>
#include <array>
#include <vector>

namespace swba::estimators
{
enum class PoseModel
{
	/** Planar when the data is (io::is_planar: 2D odometry, readings without pitch), else 6D. The
	 * window decides at its first step (io::is_planar_step), the batch and the EKF on all steps. */
	Auto,
	Spatial,  ///< SE(3) poses, 3D landmarks, readings (range, yaw, pitch)
	Planar	  ///< SE(2) poses, landmarks at the sensor's height, readings (range, yaw)
};
constexpr std::array<EnumName<PoseModel>, 3> enum_names(PoseModel)
{
	return {{{PoseModel::Auto, "auto"}, {PoseModel::Spatial, "6d"}, {PoseModel::Planar, "2d"}}};
}

/** Rows of a bearing-range reading, the degrees of freedom of its χ² tests: 2 in the planar model
 * (range, yaw), else 3 (range, yaw, pitch). */
constexpr int reading_dof(PoseModel model) { return model == PoseModel::Planar ? 2 : 3; }

/** Marginal covariance of a pose in the solver's tangent convention: right perturbation
 * T = T̂·Exp(δ), δ = [ρ, ω] (t ← t + R ρ, R ← R Exp(ω)), as SE3Manifold. A planar pose's 3×3 over
 * (ρx, ρy, ωz) sits at rows and columns (0, 1, 5), the other entries zero. NaN where it could not
 * be computed (doc/formats.md, "Covariance files"). */
using PoseCovariance = Eigen::Matrix<double, 6, 6>;

/** A landmark's final estimate: world position and its marginal covariance (planar: the 2×2 of
 * (x, y), z row and column zero). */
struct LandmarkEstimate
{
	Eigen::Vector3d position = Eigen::Vector3d::Zero();
	Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
};


/** `model`, with Auto resolved on `steps` (Planar when io::is_planar(steps)). */
PoseModel resolve_pose_model(PoseModel model, const std::vector<io::RawlogStep>& steps);
}  // namespace swba::estimators
