/** \file range_bearing.h
 * Range-bearing factors for MRPT's CObservationBearingRange sensor model, with landmarks as world
 * XYZ points or as inverse depth in their anchor (first observing) pose.
 *
 * Sensor model (MRPT): S = T ⊕ sensor_on_robot, l = S⁻¹ ⊕ p_world (the landmark in the sensor frame),
 *   range = ‖l‖,  yaw = atan2(l.y, l.x),  pitch = −asin(l.z / range)  (computed as −atan2(l.z, ‖l.xy‖)),
 *   residual = [range − z_range, wrap(yaw − z_yaw), wrap(pitch − z_pitch)], angles wrapped to (−π, π].
 * The caller sets the information, usually diag(1/σ_range², 1/σ_yaw², 1/σ_pitch²).
 *
 * Inverse-depth landmark λ = [θ, φ, ρ] (Euclidean 3: azimuth, elevation in MRPT's pitch convention,
 * inverse range), a point in the ANCHOR's SENSOR frame:
 *   l_a(λ) = (1/ρ)·[cos φ cos θ, cos φ sin θ, −sin φ],   p_world = T_anchor ⊕ S_anchor ⊕ l_a,
 * so that the anchor's own measurement initialises λ = [yaw, pitch, 1/range] exactly.
 *
 * Pose variables are SE3Manifold values (12 doubles, row-major [R | t], right perturbation). */
#pragma once

#include <swba/core/factor.h>
#include <swba/core/lie.h>  // wrap_to_pi

#include <mrpt/poses/CPose3D.h>

#include <Eigen/Core>

namespace swba
{
/** One range-bearing reading (metres, radians), as in CObservationBearingRange::TMeasurement. */
struct RangeBearingMeasurement
{
	double range = 0, yaw = 0, pitch = 0;
};

/** The sensor model h(l) = [‖l‖, atan2(l.y, l.x), −asin(l.z/‖l‖)] of a point l in the sensor frame,
 * and optionally its 3×3 Jacobian ∂h/∂l. Returns false (h unusable) when l is not finite, l = 0 or
 * l lies on the sensor's z axis (l.x = l.y = 0: yaw undefined). */
bool range_bearing_model(const Eigen::Vector3d& l, Eigen::Vector3d& h, Eigen::Matrix3d* dh_dl = nullptr);

/** Range-bearing observation of a world XYZ landmark.
 * Variables: x[0] = T (robot pose, SE3Manifold), x[1] = p (world point, Euclidean 3).
 * With q = Rᵀ(p − t) (robot frame) and l = R_sᵀ(q − t_s):
 *   ∂l/∂δT = [−R_sᵀ, R_sᵀ[q]×],  ∂l/∂p = R_sᵀRᵀ;  J = ∂h/∂l · ∂l/∂(·). */
class RangeBearingXyzFactor final : public Factor
{
   public:
	/** Throws std::invalid_argument if the range is not > 0 or a value is not finite. */
	RangeBearingXyzFactor(const RangeBearingMeasurement& measured,
						  const mrpt::poses::CPose3D& sensor_on_robot);

	bool evaluate(const double* const* x, double* residual, double* const* jacobians) const override;

	const RangeBearingMeasurement& measured() const { return z_; }
	const mrpt::poses::CPose3D& sensor_on_robot() const { return sensor_; }

   private:
	RangeBearingMeasurement z_;
	mrpt::poses::CPose3D sensor_;
	Eigen::Matrix3d Rs_;
	Eigen::Vector3d ts_;
};

/** Range-bearing observation of an inverse-depth landmark from a pose other than its anchor.
 * Variables: x[0] = T_anchor (SE3Manifold), x[1] = T_obs (SE3Manifold), x[2] = λ (Euclidean 3).
 * The two poses must be different variables (use RangeBearingInverseDepthAnchorFactor for the
 * anchor's own observations). Returns false when ρ ≤ 0, a value is not finite or the model is
 * undefined (see range_bearing_model).
 * With s_a = R_sa·l_a + t_sa (anchor robot frame), p = R_a·s_a + t_a, q = R_oᵀ(p − t_o),
 * l = R_soᵀ(q − t_so):
 *   ∂l/∂δT_a = R_soᵀR_oᵀR_a·[I, −[s_a]×],  ∂l/∂δT_o = [−R_soᵀ, R_soᵀ[q]×],
 *   ∂l/∂λ = R_soᵀR_oᵀR_aR_sa·∂l_a/∂λ. */
class RangeBearingInverseDepthFactor final : public Factor
{
   public:
	/** Both poses carry the same sensor (`sensor_on_robot`). */
	RangeBearingInverseDepthFactor(const RangeBearingMeasurement& measured,
								   const mrpt::poses::CPose3D& sensor_on_robot);
	/** The landmark was anchored by a sensor at `anchor_sensor_on_robot` and is now observed by one at
	 * `sensor_on_robot`. Throws std::invalid_argument if the range is not > 0 or a value is not finite. */
	RangeBearingInverseDepthFactor(const RangeBearingMeasurement& measured,
								   const mrpt::poses::CPose3D& sensor_on_robot,
								   const mrpt::poses::CPose3D& anchor_sensor_on_robot);

	bool evaluate(const double* const* x, double* residual, double* const* jacobians) const override;

	const RangeBearingMeasurement& measured() const { return z_; }
	const mrpt::poses::CPose3D& sensor_on_robot() const { return sensor_; }
	const mrpt::poses::CPose3D& anchor_sensor_on_robot() const { return anchor_sensor_; }

   private:
	RangeBearingMeasurement z_;
	mrpt::poses::CPose3D sensor_, anchor_sensor_;
	Eigen::Matrix3d Rs_, Rsa_;
	Eigen::Vector3d ts_, tsa_;
};

/** The anchor's own range-bearing observation of an inverse-depth landmark: its prediction
 * h(l_a(λ)) depends on λ only (= [1/ρ, θ, φ] up to angle wrapping when |φ| < π/2).
 * Variable: x[0] = λ (Euclidean 3). Returns false when ρ ≤ 0 or a value is not finite. */
class RangeBearingInverseDepthAnchorFactor final : public Factor
{
   public:
	/** Throws std::invalid_argument if the range is not > 0 or a value is not finite. */
	explicit RangeBearingInverseDepthAnchorFactor(const RangeBearingMeasurement& measured);

	bool evaluate(const double* const* x, double* residual, double* const* jacobians) const override;

	const RangeBearingMeasurement& measured() const { return z_; }

   private:
	RangeBearingMeasurement z_;
};

/** @name Inverse-depth conversions. All throw std::invalid_argument with a reason on ρ ≤ 0, non-finite
 * input or a landmark at the sensor's origin.
 * @{ */
/** l_a(λ): the point in the anchor's sensor frame. */
Eigen::Vector3d inverse_depth_to_sensor_point(const Eigen::Vector3d& lambda);
/** Its inverse: λ = [atan2(l.y, l.x), −asin(l.z/‖l‖), 1/‖l‖] (θ = 0 on the z axis). */
Eigen::Vector3d sensor_point_to_inverse_depth(const Eigen::Vector3d& l);
/** λ of a landmark first seen in `z` by the anchor: [yaw, pitch, 1/range]. */
Eigen::Vector3d inverse_depth_from_measurement(const RangeBearingMeasurement& z);
/** p_world = T_anchor ⊕ sensor_on_robot ⊕ l_a(λ). `anchor_pose`: SE3Manifold storage (12 doubles). */
Eigen::Vector3d inverse_depth_to_world(const double* anchor_pose, const mrpt::poses::CPose3D& sensor_on_robot,
									   const Eigen::Vector3d& lambda);
Eigen::Vector3d inverse_depth_to_world(const mrpt::poses::CPose3D& anchor_pose,
									   const mrpt::poses::CPose3D& sensor_on_robot,
									   const Eigen::Vector3d& lambda);
/** λ of the world point `p_world` anchored at `anchor_pose` (inverse of inverse_depth_to_world). */
Eigen::Vector3d world_to_inverse_depth(const double* anchor_pose, const mrpt::poses::CPose3D& sensor_on_robot,
									   const Eigen::Vector3d& p_world);
Eigen::Vector3d world_to_inverse_depth(const mrpt::poses::CPose3D& anchor_pose,
									   const mrpt::poses::CPose3D& sensor_on_robot,
									   const Eigen::Vector3d& p_world);
/** Re-anchors λ from `old_anchor` (sensor `old_sensor_on_robot`) to `new_anchor` (sensor
 * `new_sensor_on_robot`): the same world point, parameterised in the new anchor's sensor frame. */
Eigen::Vector3d reanchor_inverse_depth(const double* old_anchor, const mrpt::poses::CPose3D& old_sensor_on_robot,
									   const double* new_anchor, const mrpt::poses::CPose3D& new_sensor_on_robot,
									   const Eigen::Vector3d& lambda);
Eigen::Vector3d reanchor_inverse_depth(const mrpt::poses::CPose3D& old_anchor,
									   const mrpt::poses::CPose3D& old_sensor_on_robot,
									   const mrpt::poses::CPose3D& new_anchor,
									   const mrpt::poses::CPose3D& new_sensor_on_robot,
									   const Eigen::Vector3d& lambda);
/** @} */
}  // namespace swba
