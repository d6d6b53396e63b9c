/** \file pose_model.h
 * Which robot the estimators model: a 6D robot (SE(3) poses, 3D landmarks, range-yaw-pitch readings)
 * or a planar one (SE(2) poses, landmarks on the sensor's plane, range-yaw readings), and how the
 * choice is made from the data. */
#pragma once

#include <swba/core/names.h>
#include <swba/io/rawlog.h>

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

/** `model`, with Auto resolved on `steps` (Planar when io::is_planar(steps)). */
PoseModel resolve_pose_model(PoseModel model, const std::vector<io::RawlogStep>& steps);
}  // namespace swba::estimators
