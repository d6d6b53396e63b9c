/** \file between_pose.h
 * SE(3) relative-pose (odometry) factor. The SO(3) / SE(3) helpers it is built from
 * (so3_right_jacobian_inverse, se3_pseudo_log) are in swba/core/lie.h, included here.
 *
 * Convention (as SE3Manifold and mrpt::poses::Lie::SE<3>): T ⊞ δ = T·PseudoExp(δ), δ = [ρ, ω],
 * PseudoLog(T) = [t, Log(R)]; y ⊟ x = PseudoLog(x⁻¹·y). */
#pragma once

#include <swba/core/lie.h>
#include <swba/factors/pose_error.h>

#include <mrpt/poses/CPose3D.h>

namespace swba
{
/** Relative pose ("between", odometry) factor.
 *
 *   r = PseudoLog(Z⁻¹·Ti⁻¹·Tj) = Tj ⊟ (Ti·Z) ∈ R⁶ (translation first, then rotation),
 *
 * the residual of MRPT's graph-SLAM edges. Variables: x[0] = Ti, x[1] = Tj (SE3Manifold, 12 doubles).
 * Jacobians (6×6, row-major), with E = Z⁻¹Ti⁻¹Tj, φ = Log(R_E), d = Riᵀ(tj − ti):
 *   ∂r/∂δi = [[−R_zᵀ, R_zᵀ[d]×], [0, −J_r⁻¹(φ)·R_jᵀR_i]],  ∂r/∂δj = [[R_E, 0], [0, J_r⁻¹(φ)]].
 * The information matrix (6×6, in the order of r) is set by the caller (set_information).
 * `measured` is Z, the pose of j in the frame of i (e.g. an odometry increment). */
class BetweenPoseFactor final : public PoseErrorFactor
{
   public:
	explicit BetweenPoseFactor(const mrpt::poses::CPose3D& measured);
	bool evaluate(const double* const* x, double* residual, double* const* jacobians) const override;
};
}  // namespace swba
