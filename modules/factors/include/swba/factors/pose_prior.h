/** \file pose_prior.h
 * Unary SE(3) prior: for gauge priors (fix a pose softly with a weight) and tests. */
#pragma once

#include <swba/core/factor.h>

#include <mrpt/poses/CPose3D.h>

#include <Eigen/Core>

namespace swba
{
/** Prior on one SE(3) pose.
 *
 *   r = T ⊟ Z = PseudoLog(Z⁻¹·T) = [R_zᵀ(t − t_z), Log(R_zᵀR)] ∈ R⁶ (SE3Manifold::minus semantics).
 *
 * Variable: x[0] = T (SE3Manifold). Jacobian (6×6): ∂r/∂δ = [[R_zᵀR, 0], [0, J_r⁻¹(Log(R_zᵀR))]].
 * Weight with set_sigma / set_information (order: translation, rotation). */
class PosePriorFactor final : public Factor
{
   public:
	explicit PosePriorFactor(const mrpt::poses::CPose3D& prior);

	bool evaluate(const double* const* x, double* residual, double* const* jacobians) const override;

	const mrpt::poses::CPose3D& prior() const { return prior_; }

   private:
	mrpt::poses::CPose3D prior_;
	Eigen::Matrix3d Rz_;
	Eigen::Vector3d tz_;
};
}  // namespace swba
