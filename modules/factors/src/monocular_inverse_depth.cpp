#include <swba/factors/monocular_inverse_depth.h>

#include <swba/core/lie.h>
#include <swba/core/manifold.h>

#include <cmath>
#include <stdexcept>

namespace swba
{
MonocularInverseDepthFactor::MonocularInverseDepthFactor(const Eigen::Vector2d& host_bearing,
														 const Eigen::Vector2d& observed)
	: Factor(2, {SE3Manifold::kTangent, SE3Manifold::kTangent, 1}), host_bearing_(host_bearing), observed_(observed)
{
	if (!host_bearing.allFinite() || !observed.allFinite())
		throw std::invalid_argument("MonocularInverseDepthFactor: non-finite bearing or observation");
}

bool MonocularInverseDepthFactor::evaluate(const double* const* x, double* residual, double* const* jacobians) const
{
	const double lambda = x[2][0];
	if (!std::isfinite(lambda) || !(lambda > 0)) return false;
	const auto Th = se3_view(x[0]);
	const auto Tt = se3_view(x[1]);
	const Eigen::Matrix3d Rh = Th.leftCols<3>(), Rt = Tt.leftCols<3>();
	const Eigen::Vector3d b(host_bearing_.x(), host_bearing_.y(), 1.0);
	const Eigen::Vector3d dt = Th.col(3) - Tt.col(3);
	const Eigen::Vector3d q = Rt.transpose() * (Rh * b + lambda * dt);	// λ·p_t
	if (!(q.z() > 0) || !q.allFinite()) return false;						// behind the target camera
	const double iz = 1.0 / q.z();
	residual[0] = q.x() * iz - observed_.x();
	residual[1] = q.y() * iz - observed_.y();
	if (!std::isfinite(residual[0]) || !std::isfinite(residual[1])) return false;
	if (!jacobians) return true;
	Eigen::Matrix<double, 2, 3> P;
	P << iz, 0.0, -q.x() * iz * iz, 0.0, iz, -q.y() * iz * iz;
	using Matrix26RowMajor = Eigen::Matrix<double, 2, 6, Eigen::RowMajor>;
	if (jacobians[0])
	{
		const Eigen::Matrix<double, 2, 3> PRtRh = P * Rt.transpose() * Rh;
		Eigen::Map<Matrix26RowMajor> J(jacobians[0]);
		J.leftCols<3>() = lambda * PRtRh;
		J.rightCols<3>() = -PRtRh * skew(b);
	}
	if (jacobians[1])
	{
		Eigen::Map<Matrix26RowMajor> J(jacobians[1]);
		J.leftCols<3>() = -lambda * P;
		J.rightCols<3>() = P * skew(q);
	}
	if (jacobians[2])
	{
		Eigen::Map<Eigen::Vector2d> J(jacobians[2]);
		J = P * Rt.transpose() * dt;
	}
	return true;
}
}  // namespace swba
