#include <swba/core/lie.h>
#include <swba/factors/snavely_reprojection.h>

#include <Eigen/Geometry>
#include <cmath>

namespace swba
{
Eigen::Vector3d angle_axis_rotate_point(const double* omega, const Eigen::Vector3d& X)
{
	const Eigen::Map<const Eigen::Vector3d> w(omega);
	const RodriguesCoefficients k = rodrigues_coefficients(w.squaredNorm());
	const Eigen::Vector3d wX = w.cross(X);
	return X + k.a * wX + k.b * w.cross(wX);
}

Eigen::Vector3d snavely_camera_centre(const double* camera)
{
	// c = −Rᵀ t and R(ω)ᵀ = R(−ω).
	const double minus_omega[3] = {-camera[0], -camera[1], -camera[2]};
	return -angle_axis_rotate_point(minus_omega, Eigen::Vector3d(camera[3], camera[4], camera[5]));
}

SnavelyReprojectionFactor::SnavelyReprojectionFactor(double observed_x, double observed_y)
	: Factor(2, {kCameraDim, kPointDim}), observed_{observed_x, observed_y}
{
}

bool SnavelyReprojectionFactor::evaluate(const double* const* x, double* residual,
										 double* const* jacobians) const
{
	const double* cam = x[0];
	const Eigen::Map<const Eigen::Vector3d> omega(cam);
	const Eigen::Map<const Eigen::Vector3d> X(x[1]);
	const double f = cam[6], k1 = cam[7], k2 = cam[8];

	const RodriguesCoefficients rc = rodrigues_coefficients(omega.squaredNorm());
	const Eigen::Vector3d wX = omega.cross(X);
	const Eigen::Vector3d Q = X + rc.a * wX + rc.b * omega.cross(wX);  // R(ω)·X
	const Eigen::Vector3d P(Q.x() + cam[3], Q.y() + cam[4], Q.z() + cam[5]);
	if (P.z() == 0.0) return false;

	const double inv_z = 1.0 / P.z();
	const Eigen::Vector2d p(-P.x() * inv_z, -P.y() * inv_z);
	const double n = p.squaredNorm();
	const double radial = 1.0 + n * (k1 + k2 * n);
	residual[0] = f * radial * p.x() - observed_[0];
	residual[1] = f * radial * p.y() - observed_[1];
	if (!std::isfinite(residual[0]) || !std::isfinite(residual[1])) return false;
	if (!jacobians || (!jacobians[0] && !jacobians[1])) return true;

	// du/dp = f (r I + 2 (k1 + 2 k2 n) p pᵀ); dp/dP = −(1/P.z) [I₂ | p]; J_P = du/dp · dp/dP.
	const double dr_dn2 = 2.0 * (k1 + 2.0 * k2 * n);
	Eigen::Matrix2d du_dp = (dr_dn2 * p) * p.transpose();
	du_dp.diagonal().array() += radial;
	du_dp *= f;
	Eigen::Matrix<double, 2, 3> J_P;
	J_P.leftCols<2>() = -inv_z * du_dp;
	J_P.col(2) = J_P.leftCols<2>() * p;

	const Eigen::Matrix3d W = skew(omega);
	if (jacobians[0])
	{
		Eigen::Map<Eigen::Matrix<double, 2, 9, Eigen::RowMajor>> Jc(jacobians[0]);
		// ∂P/∂ω = −[Q]× J_l(ω), J_l = I + b W + c W².
		const Eigen::Matrix3d W2 = W * W;
		Eigen::Matrix3d J_l = rc.b * W + rc.c * W2;
		J_l.diagonal().array() += 1.0;
		const Eigen::Matrix<double, 2, 3> J_PQ = J_P * skew(Q);
		Jc.leftCols<3>() = -J_PQ * J_l;
		Jc.middleCols<3>(3) = J_P;
		Jc.col(6) = radial * p;
		Jc.col(7) = (f * n) * p;
		Jc.col(8) = (f * n * n) * p;
	}
	if (jacobians[1])
	{
		Eigen::Map<Eigen::Matrix<double, 2, 3, Eigen::RowMajor>> Jp(jacobians[1]);
		Eigen::Matrix3d R = rc.a * W + rc.b * (W * W);
		R.diagonal().array() += 1.0;
		Jp = J_P * R;
	}
	return true;
}
}  // namespace swba
