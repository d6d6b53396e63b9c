/** \file monocular_inverse_depth.h
 * Reprojection error of a point parameterised by its inverse depth in a host camera
 * on the normalised image plane.
 *
 * Camera poses T_wc are camera-to-world (SE3Manifold, right perturbation). The point is hosted in
 * camera h with a FIXED normalised bearing b = [u_h, v_h, 1] (its first observation) and a 1-D
 * inverse depth λ (Euclidean 1):
 *   p_h = b/λ,  p_t = T_t⁻¹·T_h·p_h,  r = [p_t.x/p_t.z − u_obs, p_t.y/p_t.z − v_obs].
 * The projection is scale invariant, so it is evaluated on q = λ·p_t = R_tᵀ(R_h·b + λ(t_h − t_t)),
 * which stays finite as λ → 0 (points at infinity). */
#pragma once

#include <swba/core/factor.h>

#include <Eigen/Core>

namespace swba
{
/** Variables: x[0] = T_host, x[1] = T_target (SE3Manifold, distinct variables), x[2] = λ (Euclidean 1).
 * Jacobians (2×6, 2×6, 2×1), with P = ∂π/∂q = [[1/q_z, 0, −q_x/q_z²], [0, 1/q_z, −q_y/q_z²]]:
 *   ∂r/∂δT_h = P·R_tᵀR_h·[λI, −[b]×],  ∂r/∂δT_t = P·[−λI, [q]×],  ∂r/∂λ = P·R_tᵀ(t_h − t_t).
 * Returns false when λ ≤ 0, p_t.z ≤ 0 (point behind the target camera) or a value is not finite. */
class MonocularInverseDepthFactor final : public Factor
{
   public:
	/** `host_bearing` = (u_h, v_h) and `observed` = (u_obs, v_obs) on the normalised image plane.
	 * Throws std::invalid_argument on non-finite values. */
	MonocularInverseDepthFactor(const Eigen::Vector2d& host_bearing, const Eigen::Vector2d& observed);

	bool evaluate(const double* const* x, double* residual, double* const* jacobians) const override;

	const Eigen::Vector2d& host_bearing() const { return host_bearing_; }
	const Eigen::Vector2d& observed() const { return observed_; }

   private:
	Eigen::Vector2d host_bearing_, observed_;
};
}  // namespace swba
