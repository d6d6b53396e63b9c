#include <swba/core/lie.h>

#include <mrpt/poses/Lie/SO.h>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <cmath>

namespace swba
{
// ---------------------------------------------------------------- small-angle series
// Every SO(3) coefficient whose closed form cancels near θ = 0 is evaluated here.

RodriguesCoefficients rodrigues_coefficients(double theta_sq)
{
	RodriguesCoefficients k;
	if (theta_sq < 1e-2)
	{
		const double t2 = theta_sq, t4 = t2 * t2, t6 = t4 * t2, t8 = t4 * t4;
		k.a = 1.0 - t2 / 6.0 + t4 / 120.0 - t6 / 5040.0 + t8 / 362880.0;
		k.b = 0.5 - t2 / 24.0 + t4 / 720.0 - t6 / 40320.0 + t8 / 3628800.0;
		k.c = 1.0 / 6.0 - t2 / 120.0 + t4 / 5040.0 - t6 / 362880.0 + t8 / 39916800.0;
	}
	else
	{
		const double theta = std::sqrt(theta_sq);
		const double s = std::sin(theta);
		const double half_s = std::sin(0.5 * theta);
		k.a = s / theta;
		k.b = 2.0 * half_s * half_s / theta_sq;
		k.c = (theta - s) / (theta_sq * theta);
	}
	return k;
}

namespace
{
/** c(θ) = 1/θ² − (1 + cos θ)/(2θ sin θ) = 1/θ² − 1/(2θ tan(θ/2)) of J_r⁻¹; the second form has no 0/0
 * at π, and below θ = 1e-4 the series 1/12 + θ²/720 (next term θ⁴/30240 < 4e-21). */
double right_jacobian_inverse_coefficient(double theta_sq)
{
	const double theta = std::sqrt(theta_sq);
	if (theta < 1e-4) return 1.0 / 12.0 + theta_sq / 720.0;
	return 1.0 / theta_sq - 1.0 / (2.0 * theta * std::tan(0.5 * theta));
}
}  // namespace

// ---------------------------------------------------------------- SO(3) / SE(3)

Eigen::Matrix3d so3_right_jacobian(const Eigen::Vector3d& phi)
{
	const RodriguesCoefficients k = rodrigues_coefficients(phi.squaredNorm());
	const Eigen::Matrix3d S = skew(phi);
	return Eigen::Matrix3d::Identity() - k.b * S + k.c * S * S;
}

Eigen::Matrix3d so3_exp(const Eigen::Vector3d& phi)
{
	mrpt::math::CVectorFixedDouble<3> w;
	for (int i = 0; i < 3; i++) w[i] = phi[i];
	return mrpt::poses::Lie::SO<3>::exp(w).asEigen();
}

Eigen::Vector3d so3_log(const Eigen::Matrix3d& R)
{
	const Eigen::AngleAxisd aa(Eigen::Quaterniond(R).normalized());
	return aa.angle() * aa.axis();
}

Eigen::Matrix3d so3_right_jacobian_inverse(const Eigen::Vector3d& phi)
{
	const double c = right_jacobian_inverse_coefficient(phi.squaredNorm());
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

Eigen::Matrix3d project_to_so3(const Eigen::Matrix3d& A)
{
	const Eigen::JacobiSVD<Eigen::Matrix3d> svd(A, Eigen::ComputeFullU | Eigen::ComputeFullV);
	Eigen::Matrix3d U = svd.matrixU();
	if ((U * svd.matrixV().transpose()).determinant() < 0) U.col(2) = -U.col(2);
	return U * svd.matrixV().transpose();
}

// ---------------------------------------------------------------- SO(2)

double wrap_to_pi(double a)
{
	a = std::remainder(a, 2.0 * M_PI);  // in [−π, π]
	if (a <= -M_PI) a += 2.0 * M_PI;
	return a;
}
}  // namespace swba
