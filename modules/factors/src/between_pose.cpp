#include <swba/factors/between_pose.h>

#include <swba/core/lie.h>
#include <swba/core/manifold.h>

namespace swba
{
namespace
{
using Matrix66RowMajor = Eigen::Matrix<double, 6, 6, Eigen::RowMajor>;

Eigen::Matrix3d rotation_of(const mrpt::poses::CPose3D& pose) { return pose.getRotationMatrix().asEigen(); }
}  // namespace

BetweenPoseFactor::BetweenPoseFactor(const mrpt::poses::CPose3D& measured)
	: Factor(6, {SE3Manifold::kTangent, SE3Manifold::kTangent}),
	  measured_(measured),
	  Rz_(rotation_of(measured)),
	  tz_(measured.x(), measured.y(), measured.z())
{
}

bool BetweenPoseFactor::evaluate(const double* const* x, double* residual, double* const* jacobians) const
{
	const auto Ti = se3_view(x[0]);
	const auto Tj = se3_view(x[1]);
	const Eigen::Matrix3d Ri = Ti.leftCols<3>(), Rj = Tj.leftCols<3>();
	const Eigen::Vector3d d = Ri.transpose() * (Tj.col(3) - Ti.col(3));  // tj in the frame of i
	const Eigen::Matrix3d RE = Rz_.transpose() * Ri.transpose() * Rj;	  // E = Z⁻¹·Ti⁻¹·Tj
	const Eigen::Vector3d tE = Rz_.transpose() * (d - tz_);
	const Eigen::Matrix<double, 6, 1> r = se3_pseudo_log(RE, tE);
	if (!r.allFinite()) return false;
	Eigen::Map<Eigen::Matrix<double, 6, 1>> r_out(residual);
	r_out = r;
	if (!jacobians) return true;
	const Eigen::Matrix3d Jinv = so3_right_jacobian_inverse(r.tail<3>());
	if (jacobians[0])
	{
		Eigen::Map<Matrix66RowMajor> J(jacobians[0]);
		J.setZero();
		J.block<3, 3>(0, 0) = -Rz_.transpose();
		J.block<3, 3>(0, 3) = Rz_.transpose() * skew(d);
		J.block<3, 3>(3, 3) = -Jinv * Rj.transpose() * Ri;
	}
	if (jacobians[1])
	{
		Eigen::Map<Matrix66RowMajor> J(jacobians[1]);
		J.setZero();
		J.block<3, 3>(0, 0) = RE;
		J.block<3, 3>(3, 3) = Jinv;
	}
	return true;
}
}  // namespace swba
