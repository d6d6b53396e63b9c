/** \file pose_prior.h
 * Unary SE(3) prior: for gauge priors (fix a pose softly with a weight) and tests. */
#pragma once

#include <swba/factors/pose_error.h>

#include <mrpt/poses/CPose3D.h>

namespace swba
{
/** Prior on one SE(3) pose.
 *
 *   r = T ⊟ Z = PseudoLog(Z⁻¹·T) = [R_zᵀ(t − t_z), Log(R_zᵀR)] ∈ R⁶ (SE3Manifold::minus semantics).
 *
 * Variable: x[0] = T (SE3Manifold). Jacobian (6×6): ∂r/∂δ = [[R_zᵀR, 0], [0, J_r⁻¹(Log(R_zᵀR))]].
 * Weight with set_sigma / set_information (order: translation, rotation). The prior Z is measured(). */
class PosePriorFactor final : public PoseErrorFactor
{
   public:
	explicit PosePriorFactor(const mrpt::poses::CPose3D& prior);
	const mrpt::poses::CPose3D& prior() const { return measured(); }
	bool evaluate(const double* const* x, double* residual, double* const* jacobians) const override;
};
}  // namespace swba
