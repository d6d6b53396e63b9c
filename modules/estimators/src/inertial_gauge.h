/** \file inertial_gauge.h (private to the estimators module)
 * The four-DoF gauge of the inertial window without pose priors: IMU + relative poses leave the world
 * translation (x, y, z) and the rotation about the vertical (yaw) unobservable; gravity observes roll and
 * pitch. The fixed gauge makes those four directions of the first keyframe's pose constant (TiltManifold,
 * with TiltFactor for the factors on it); the free gauge gives them no information, picks the frame of
 * each solve by anchoring them on the first keyframe's pose, which the window keeps in the model as its
 * reference (inertial_gauge_anchor), and undoes what motion is left after it (hold_inertial_gauge). */
#pragma once

#include <swba/core/factor.h>
#include <swba/core/manifold.h>
#include <swba/nonlinear/problem.h>

#include <Eigen/Core>
#include <map>
#include <memory>
#include <vector>

namespace swba::estimators::detail
{
/** SE(3) storage, updates (δpitch, δroll) of MRPT's yaw-pitch-roll (ZYX) angles: x, y, z and yaw are never
 * moved. Valid away from pitch ±90°. */
class TiltManifold final : public Manifold
{
   public:
	int ambient_size() const override { return SE3Manifold::kAmbient; }
	int tangent_size() const override { return 2; }
	void plus(const double* x, const double* delta, double* x_plus) const override;
	/** Pitch and roll differences (wrapped to (−π, π]); yaw and position differences are dropped. */
	void minus(const double* y, const double* x, double* delta) const override;
	static std::shared_ptr<const TiltManifold> instance();
	/** 6×2: the SE3Manifold tangent [ρ, ω] of a (δpitch, δroll) update at x: ρ = 0, ω = [Rx(roll)ᵀe_y, e_x]. */
	static Eigen::Matrix<double, 6, 2> basis(const double* x);
};

/** `inner` with its variable `held` on TiltManifold (the others unchanged): J_held = J_inner,held·basis(x).
 * The information is `inner`'s. */
class TiltFactor final : public Factor
{
   public:
	TiltFactor(std::shared_ptr<const Factor> inner, int held);
	bool evaluate(const double* const* x, double* residual, double* const* jacobians) const override;

   private:
	std::shared_ptr<const Factor> inner_;
	int held_;
};

/** W (6×6, rank 2) of a PosePriorFactor at Z that weighs only the rotations about the world's x and y axes,
 * each with σ `tilt_sigma`: the gauge directions carry no information. */
Eigen::Matrix<double, 6, 6> tilt_prior_sqrt_information(const Eigen::Matrix3d& R_Z, double tilt_sigma);

/** The free gauge's reference: the pose the window's frame is held to, at the value it is held at. */
struct InertialGaugeReference
{
	VariableId id = -1;		   ///< −1: no free gauge
	std::vector<double> pose;  ///< SE3Manifold ambient value
};

/** A PosePriorFactor at the reference's pose that weighs only its world position and its rotation about the
 * world's z (σ 1e-6 m, rad): it keeps LM from sliding along the four directions without informing anything
 * else (the free gauge's linear systems have no information along them). */
std::shared_ptr<Factor> inertial_gauge_anchor(const InertialGaugeReference& at);

/** Moves every pose and velocity of `window` (a velocity id < 0: a pose without one) by the four-DoF motion
 * [u, w] (a world translation u and a rotation by w about the world's z) that brings the reference pose back
 * to its position and its yaw in `at` (MRPT's ZYX yaw, the angle the fixed gauge holds: a rotation about z
 * on the left adds to it exactly): p ← Rz(−w)p − u, R ← Rz(−w)R, v ← Rz(−w)v. Every factor of the window is
 * invariant under it. */
void hold_inertial_gauge(Problem& problem, const InertialGaugeReference& at,
						 const std::vector<std::pair<VariableId, VariableId>>& window);
}  // namespace swba::estimators::detail
