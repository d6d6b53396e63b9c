#include <swba/factors/between_pose.h>
#include <swba/factors/pose_prior.h>

#include <swba/core/manifold.h>

namespace swba
{
PosePriorFactor::PosePriorFactor(const mrpt::poses::CPose3D& prior)
	: Factor(6, {SE3Manifold::kTangent}),
	  prior_(prior),
	  Rz_(prior.getRotationMatrix().asEigen()),
	  tz_(prior.x(), prior.y(), prior.z())
{
}

bool PosePriorFactor::evaluate(const double* const* x, double* residual, double* const* jacobians) const
{
	const auto T = se3_view(x[0]);
	const Eigen::Matrix3d RE = Rz_.transpose() * T.leftCols<3>();  // E = Z⁻¹·T
	const Eigen::Vector3d tE = Rz_.transpose() * (T.col(3) - tz_);
	const Eigen::Matrix<double, 6, 1> r = se3_pseudo_log(RE, tE);
	if (!r.allFinite()) return false;
	Eigen::Map<Eigen::Matrix<double, 6, 1>> r_out(residual);
	r_out = r;
	if (jacobians && jacobians[0])
	{
		Eigen::Map<Eigen::Matrix<double, 6, 6, Eigen::RowMajor>> J(jacobians[0]);
		J.setZero();
		J.block<3, 3>(0, 0) = RE;
		J.block<3, 3>(3, 3) = so3_right_jacobian_inverse(r.tail<3>());
	}
	return true;
}
}  // namespace swba
