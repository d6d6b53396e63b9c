#include <swba/factors/between_pose.h>

#include <swba/core/manifold.h>

#include <mrpt/poses/Lie/SO.h>

#include <cmath>

namespace swba
{
namespace
{
using Matrix66RowMajor = Eigen::Matrix<double, 6, 6, Eigen::RowMajor>;

Eigen::Matrix3d rotation_of(const mrpt::poses::CPose3D& pose) { return pose.getRotationMatrix().asEigen(); }
}  // namespace

Eigen::Matrix3d so3_right_jacobian_inverse(const Eigen::Vector3d& phi)
{
	const double theta2 = phi.squaredNorm();
	const double theta = std::sqrt(theta2);
	// c(θ) = 1/θ² − (1 + cos θ)/(2θ sin θ) = 1/θ² − 1/(2θ tan(θ/2)); the second form has no 0/0 at π.
	double c;
	if (theta < 1e-4)
		c = 1.0 / 12.0 + theta2 / 720.0;  // next term θ⁴/30240 < 4e-21
	else
		c = 1.0 / theta2 - 1.0 / (2.0 * theta * std::tan(0.5 * theta));
	const Eigen::Matrix3d S = skew(phi);
	return Eigen::Matrix3d::Identity() + 0.5 * S + c * S * S;
}

Eigen::Matrix<double, 6, 1> se3_pseudo_log(const Eigen::Matrix3d& R, const Eigen::Vector3d& t)
{
	mrpt::math::CMatrixDouble33 M;
	M.asEigen() = R;
	const auto w = mrpt::poses::Lie::SO<3>::log(M);
	Eigen::Matrix<double, 6, 1> r;
	r << t, w[0], w[1], w[2];
	return r;
}

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
