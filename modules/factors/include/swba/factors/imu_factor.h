/** \file imu_factor.h
 * The IMU pre-integration factor between two keyframes of PRVAG states (pose, velocity, biases), and
 * a Euclidean prior for the velocity and bias of the first keyframe. */
#pragma once

#include <swba/core/factor.h>
#include <swba/factors/imu_preintegration.h>

#include <Eigen/Core>
#include <memory>

namespace swba
{
/** IMU factor on (T_i, v_i, b_i, T_j, v_j, b_j): T ∈ SE(3) (SE3Manifold, right perturbation), v ∈ ℝ³ (world
 * velocity), b = [b_a; b_g] ∈ ℝ⁶. With the pre-integrated measurement at linearisation bias b̄, δb = b_i − b̄,
 * Δt = t_j − t_i, g the gravity and ΔR̃ = ΔR·Exp(J_Rg δb_g):
 *
 *   r_p = R_iᵀ(p_j − p_i − v_i Δt − ½ g Δt²) − (Δp + J_pa δb_a + J_pg δb_g)
 *   r_R = Log(ΔR̃ᵀ R_iᵀ R_j)
 *   r_v = R_iᵀ(v_j − v_i − g Δt) − (Δv + J_va δb_a + J_vg δb_g)
 *   r_b = b_j − b_i                                      (15 residuals, order [p, R, v, b_a, b_g])
 *
 * weighted by the inverse of the pre-integration's 15×15 covariance. Jacobians are analytic (see the
 * source for each block). The factor holds the pre-integration by shared pointer and never changes it:
 * when b_i has moved far from b̄ (ImuPreintegration::bias_far) the caller re-integrates a copy at the new
 * bias and replaces the factor. */
class ImuPreintegrationFactor final : public Factor
{
   public:
	/** Throws std::invalid_argument when the pre-integration spans no time or its covariance is not
	 * positive definite. */
	explicit ImuPreintegrationFactor(std::shared_ptr<const ImuPreintegration> preintegration);
	bool evaluate(const double* const* x, double* residual, double* const* jacobians) const override;
	const ImuPreintegration& preintegration() const { return *pim_; }
	const std::shared_ptr<const ImuPreintegration>& preintegration_ptr() const { return pim_; }

   private:
	std::shared_ptr<const ImuPreintegration> pim_;
};

/** Prior on a Euclidean variable: r = x − μ (n residuals), Jacobian I, weighted by set_information /
 * set_sigma (the first keyframe's velocity and biases). */
class EuclideanPriorFactor final : public Factor
{
   public:
	explicit EuclideanPriorFactor(const Eigen::VectorXd& mean);
	bool evaluate(const double* const* x, double* residual, double* const* jacobians) const override;
	bool constant_jacobian() const override { return true; }
	const Eigen::VectorXd& mean() const { return mean_; }

   private:
	Eigen::VectorXd mean_;
};
}  // namespace swba
