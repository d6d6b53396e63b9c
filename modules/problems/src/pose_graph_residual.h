// Internal to modules/problems: the rotation part of the reference residual of a 3D pose-graph edge,
// shared by the reference cost and the position solve of the chordal initialisation.
#pragma once

#include <swba/factors/relative_pose.h>

#include <Eigen/Geometry>

namespace swba::problems::detail
{
/** 2·vec(δq), δq = q_ab⁻¹·q_a⁻¹·q_b (G2o) or q_ab·(q_a⁻¹·q_b)⁻¹ (CeresExample), δq taken with
 * w ≥ 0 (relative_pose.h), evaluated with quaternion algebra independently of the factor. */
inline Eigen::Vector3d rotation_residual(const Eigen::Quaterniond& q_ab, const Eigen::Quaterniond& q_a,
										 const Eigen::Quaterniond& q_b, RotationError rotation_error)
{
	const Eigen::Quaterniond q_est = q_a.conjugate() * q_b;
	Eigen::Quaterniond dq = rotation_error == RotationError::G2o ? q_ab.conjugate() * q_est : q_ab * q_est.conjugate();
	if (dq.w() < 0) dq.coeffs() = -dq.coeffs();
	return 2.0 * dq.vec();
}
}  // namespace swba::problems::detail
