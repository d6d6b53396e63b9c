#include <swba/factors/pose_prior.h>

#include <swba/core/manifold.h>

namespace swba
{
PosePriorFactor::PosePriorFactor(const mrpt::poses::CPose3D& prior) : PoseErrorFactor(prior, {SE3Manifold::kTangent})
{
}

bool PosePriorFactor::evaluate(const double* const* x, double* residual, double* const* jacobians) const
{
	const auto T = se3_view(x[0]);
	const Eigen::Matrix3d& Rz = measured_rotation();
	const Eigen::Matrix3d RE = Rz.transpose() * T.leftCols<3>();  // E = Z⁻¹·T
	const Eigen::Vector3d tE = Rz.transpose() * (T.col(3) - measured_translation());
	const bool want_jacobian = jacobians && jacobians[0];
	Eigen::Matrix3d Jinv;
	if (!write_error(RE, tE, residual, want_jacobian ? &Jinv : nullptr)) return false;
	if (want_jacobian) write_error_jacobian(RE, Jinv, jacobians[0]);
	return true;
}
}  // namespace swba
