/** \file snavely_reprojection.h
 * The Snavely camera model of the BAL data sets ("Bundle Adjustment in the Large", Agarwal et al.
 * 2010) as a factor with analytic Jacobians.
 *
 * Camera (9 doubles, Euclidean): ω (Rodrigues / angle-axis, 3), t (3), f, k1, k2.
 * Point (3 doubles, Euclidean). Projection:
 *   P = R(ω)·X + t,  p = −P.xy / P.z,  r = 1 + k1‖p‖² + k2‖p‖⁴,  u = f·r·p,
 *   residual = u − observed   (pixels).
 * The rotation vector is updated additively (ω ← ω + δω), as in Ceres's BAL example, so its
 * Jacobian is ∂(R(ω)X)/∂ω = −[R(ω)X]× · J_l(ω) with J_l the left Jacobian of SO(3). */
#pragma once

#include <swba/core/factor.h>

#include <Eigen/Core>

namespace swba
{
/** R(ω)·X by Rodrigues' formula (rodrigues_coefficients: series expansion below ‖ω‖ = 0.1, exact to
 * double precision). */
Eigen::Vector3d angle_axis_rotate_point(const double* omega, const Eigen::Vector3d& X);

/** Camera centre in world coordinates, c = −R(ω)ᵀ·t, of a 9-parameter Snavely camera. */
Eigen::Vector3d snavely_camera_centre(const double* camera);

/** Reprojection error of one BAL observation: 2 residuals, variables (camera 9, point 3). */
class SnavelyReprojectionFactor final : public Factor
{
   public:
	static constexpr int kCameraDim = 9;
	static constexpr int kPointDim = 3;

	SnavelyReprojectionFactor(double observed_x, double observed_y);

	/** x[0]: camera (9), x[1]: point (3). jacobians[0]: 2×9, jacobians[1]: 2×3, row-major.
	 * Points behind the camera (P.z > 0) are evaluated as the model says (BAL's convention, as
	 * Ceres does); returns false only when P.z = 0 or the result is not finite. */
	bool evaluate(const double* const* x, double* residual, double* const* jacobians) const override;

	double observed_x() const { return observed_[0]; }
	double observed_y() const { return observed_[1]; }

   private:
	double observed_[2];
};
}  // namespace swba
