#include <swba/factors/body_velocity_prior.h>

#include <swba/core/lie.h>
#include <swba/core/manifold.h>

namespace swba
{
BodyVelocityPriorFactor::BodyVelocityPriorFactor(const Eigen::Vector3d& body_velocity)
	: Factor(3, {SE3Manifold::kTangent, 3}), body_velocity_(body_velocity)
{
}

bool BodyVelocityPriorFactor::evaluate(const double* const* x, double* residual, double* const* jacobians) const
{
	const Eigen::Matrix3d R = se3_view(x[0]).leftCols<3>();
	const Eigen::Vector3d vb = R.transpose() * Eigen::Map<const Eigen::Vector3d>(x[1]);
	Eigen::Map<Eigen::Vector3d>(residual, 3) = vb - body_velocity_;
	if (!jacobians) return true;
	// R·Exp(ω): r = Exp(ω)ᵀRᵀv ≈ (I − [ω]×)Rᵀv = Rᵀv + [Rᵀv]×ω; the translation does not enter.
	if (jacobians[0])
	{
		Eigen::Map<Eigen::Matrix<double, 3, 6, Eigen::RowMajor>> J(jacobians[0]);
		J.leftCols<3>().setZero();
		J.rightCols<3>() = skew(vb);
	}
	if (jacobians[1])
	{
		Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> J(jacobians[1]);
		J = R.transpose();
	}
	return true;
}
}  // namespace swba
