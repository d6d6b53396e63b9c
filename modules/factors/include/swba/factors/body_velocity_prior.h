/** \file body_velocity_prior.h
 * Prior on a velocity seen from the body frame of a pose: r = Rᵀv − v̄_b. Unlike a prior on the world
 * velocity v, it is invariant under any rotation of the world applied to both (R ↦ QR, v ↦ Qv), so it
 * leaves a heading gauge free (the inertial window's free gauge, doc/inertial.md). */
#pragma once

#include <swba/core/factor.h>

#include <Eigen/Core>

namespace swba
{
/** Variables: x[0] = T (SE3Manifold, rotation R), x[1] = v (R³, world frame). Residual (3):
 * r = Rᵀv − v̄_b. Jacobians: ∂r/∂[ρ, ω] = [0, [Rᵀv]×] (3×6), ∂r/∂v = Rᵀ. Weight with set_information /
 * set_sigma. */
class BodyVelocityPriorFactor final : public Factor
{
   public:
	explicit BodyVelocityPriorFactor(const Eigen::Vector3d& body_velocity);
	const Eigen::Vector3d& prior() const { return body_velocity_; }
	bool evaluate(const double* const* x, double* residual, double* const* jacobians) const override;

   private:
	Eigen::Vector3d body_velocity_;
};
}  // namespace swba
