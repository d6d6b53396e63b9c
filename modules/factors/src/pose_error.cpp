#include <swba/factors/pose_error.h>

namespace swba
{
PoseErrorFactor::PoseErrorFactor(const mrpt::poses::CPose3D& measured, std::vector<int> tangent_dims)
	: Factor(6, std::move(tangent_dims)),
	  measured_(measured),
	  Rz_(measured.getRotationMatrix().asEigen()),
	  tz_(measured.x(), measured.y(), measured.z())
{
}

bool PoseErrorFactor::write_error(const Eigen::Matrix3d& RE, const Eigen::Vector3d& tE, double* residual,
								  Eigen::Matrix3d* Jinv)
{
	const Eigen::Matrix<double, 6, 1> r = se3_pseudo_log(RE, tE);
	if (!r.allFinite()) return false;
	Eigen::Map<Eigen::Matrix<double, 6, 1>> r_out(residual);
	r_out = r;
	if (Jinv) *Jinv = so3_right_jacobian_inverse(r.tail<3>());
	return true;
}

void PoseErrorFactor::write_error_jacobian(const Eigen::Matrix3d& RE, const Eigen::Matrix3d& Jinv, double* J)
{
	Eigen::Map<Eigen::Matrix<double, 6, 6, Eigen::RowMajor>> M(J);
	M.setZero();
	M.block<3, 3>(0, 0) = RE;
	M.block<3, 3>(3, 3) = Jinv;
}
}  // namespace swba
