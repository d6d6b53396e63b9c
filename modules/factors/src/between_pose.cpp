#include <swba/factors/between_pose.h>

#include <swba/core/lie.h>
#include <swba/core/manifold.h>

namespace swba
{
BetweenPoseFactor::BetweenPoseFactor(const mrpt::poses::CPose3D& measured)
	: PoseErrorFactor(measured, {SE3Manifold::kTangent, SE3Manifold::kTangent})
{
}

bool BetweenPoseFactor::evaluate(const double* const* x, double* residual, double* const* jacobians) const
{
	const auto Ti = se3_view(x[0]);
	const auto Tj = se3_view(x[1]);
	const Eigen::Matrix3d Ri = Ti.leftCols<3>(), Rj = Tj.leftCols<3>();
	const Eigen::Vector3d d = Ri.transpose() * (Tj.col(3) - Ti.col(3));  // tj in the frame of i
	const Eigen::Matrix3d& Rz = measured_rotation();
	const Eigen::Matrix3d RE = Rz.transpose() * Ri.transpose() * Rj;	 // E = Z⁻¹·Ti⁻¹·Tj
	const Eigen::Vector3d tE = Rz.transpose() * (d - measured_translation());
	Eigen::Matrix3d Jinv;
	if (!write_error(RE, tE, residual, jacobians ? &Jinv : nullptr)) return false;
	if (!jacobians) return true;
	if (jacobians[0])
	{
		Eigen::Map<Eigen::Matrix<double, 6, 6, Eigen::RowMajor>> J(jacobians[0]);
		J.setZero();
		J.block<3, 3>(0, 0) = -Rz.transpose();
		J.block<3, 3>(0, 3) = Rz.transpose() * skew(d);
		J.block<3, 3>(3, 3) = -Jinv * Rj.transpose() * Ri;
	}
	if (jacobians[1]) write_error_jacobian(RE, Jinv, jacobians[1]);
	return true;
}
}  // namespace swba
