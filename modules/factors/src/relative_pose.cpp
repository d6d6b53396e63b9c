#include <swba/core/lie.h>
#include <swba/core/manifold.h>
#include <swba/factors/relative_pose.h>

#include <cmath>

namespace swba
{
namespace
{
using Mat36 = Eigen::Matrix<double, 3, 6, Eigen::RowMajor>;
using Mat66 = Eigen::Matrix<double, 6, 6, Eigen::RowMajor>;
using Mat33 = Eigen::Matrix3d;

/** Unit quaternion of a rotation matrix, sign chosen so that w ≥ 0. */
Eigen::Quaterniond canonical_quaternion(const Mat33& E)
{
	Eigen::Quaterniond q(E);
	if (q.w() < 0) q.coeffs() = -q.coeffs();
	return q;
}

/** ∂ 2·vec(q(E·Exp(ω))) / ∂ω at ω = 0, for q(E) = (w, v): w·I + [v]×. */
Mat33 d_twice_vec_d_right_rotation(const Eigen::Quaterniond& q)
{
	return q.w() * Mat33::Identity() + skew(q.vec());
}
}  // namespace

RelativePoseFactor::RelativePoseFactor(const Eigen::Quaterniond& q_ab, const Eigen::Vector3d& t_ab,
									   RotationError rotation_error)
	: Factor(6, {6, 6}), q_ab_(q_ab.normalized()), t_ab_(t_ab), rotation_error_(rotation_error)
{
	R_ab_ = q_ab_.toRotationMatrix();
}

bool RelativePoseFactor::evaluate(const double* const* x, double* residual, double* const* jacobians) const
{
	const auto Ta = se3_view(x[0]);
	const auto Tb = se3_view(x[1]);
	const Mat33 Ra_T = Ta.leftCols<3>().transpose();
	const Mat33 Rb = Tb.leftCols<3>();
	const Eigen::Vector3d d_a = Ra_T * (Tb.col(3) - Ta.col(3));  // R_aᵀ(t_b − t_a)
	const Mat33 Rab_est = Ra_T * Rb;                              // R_aᵀ R_b
	const bool g2o = rotation_error_ == RotationError::G2o;
	// G2o: E = R_abᵀ·R_aᵀ·R_b; CeresExample: F = R_ab·R_bᵀ·R_a.
	const Eigen::Quaterniond q_err =
		canonical_quaternion(g2o ? Mat33(R_ab_.transpose() * Rab_est) : Mat33(R_ab_ * Rab_est.transpose()));

	Eigen::Map<Eigen::Matrix<double, 6, 1>> r(residual);
	r.head<3>() = d_a - t_ab_;
	r.tail<3>() = 2.0 * q_err.vec();

	if (jacobians && (jacobians[0] || jacobians[1]))
	{
		const Mat33 D = d_twice_vec_d_right_rotation(q_err);
		// G2o: R_b ← R_b·Exp(ω) gives E·Exp(ω); R_a ← R_a·Exp(ω) gives E·Exp(−R_bᵀR_a ω).
		// CeresExample: R_a ← R_a·Exp(ω) gives F·Exp(ω); R_b ← R_b·Exp(ω) gives F·Exp(−R_aᵀR_b ω).
		const Mat33 d_rot_a = g2o ? Mat33(-D * Rab_est.transpose()) : D;
		const Mat33 d_rot_b = g2o ? D : Mat33(-D * Rab_est);
		if (jacobians[0])
		{
			Eigen::Map<Mat66> J(jacobians[0]);
			J.topLeftCorner<3, 3>() = -Mat33::Identity();
			J.topRightCorner<3, 3>() = skew(d_a);
			J.bottomLeftCorner<3, 3>().setZero();
			J.bottomRightCorner<3, 3>() = d_rot_a;
		}
		if (jacobians[1])
		{
			Eigen::Map<Mat66> J(jacobians[1]);
			J.topLeftCorner<3, 3>() = Rab_est;
			J.topRightCorner<3, 3>().setZero();
			J.bottomLeftCorner<3, 3>().setZero();
			J.bottomRightCorner<3, 3>() = d_rot_b;
		}
	}
	return true;
}

PosePriorQuatFactor::PosePriorQuatFactor(const Eigen::Quaterniond& q0, const Eigen::Vector3d& t0)
	: Factor(6, {6}), t0_(t0)
{
	R0_T_ = q0.normalized().toRotationMatrix().transpose();
}

bool PosePriorQuatFactor::evaluate(const double* const* x, double* residual, double* const* jacobians) const
{
	const auto T = se3_view(x[0]);
	const Mat33 R = T.leftCols<3>();
	const Mat33 R0T_R = R0_T_ * R;
	const Eigen::Quaterniond q_err = canonical_quaternion(R0T_R);
	Eigen::Map<Eigen::Matrix<double, 6, 1>> r(residual);
	r.head<3>() = R0_T_ * (T.col(3) - t0_);
	r.tail<3>() = 2.0 * q_err.vec();
	if (jacobians && jacobians[0])
	{
		Eigen::Map<Mat66> J(jacobians[0]);
		J.topLeftCorner<3, 3>() = R0T_R;
		J.topRightCorner<3, 3>().setZero();
		J.bottomLeftCorner<3, 3>().setZero();
		J.bottomRightCorner<3, 3>() = d_twice_vec_d_right_rotation(q_err);
	}
	return true;
}

RelativePose2dFactor::RelativePose2dFactor(double x_ab, double y_ab, double theta_ab)
	: Factor(3, {3, 3}), p_ab_(x_ab, y_ab), theta_ab_(theta_ab)
{
}

bool RelativePose2dFactor::evaluate(const double* const* x, double* residual, double* const* jacobians) const
{
	const double* a = x[0];
	const double* b = x[1];
	const double c = std::cos(a[2]), s = std::sin(a[2]);
	const double dx = b[0] - a[0], dy = b[1] - a[1];
	// R(θ_a)ᵀ·(p_b − p_a)
	residual[0] = c * dx + s * dy - p_ab_.x();
	residual[1] = -s * dx + c * dy - p_ab_.y();
	residual[2] = wrap_to_pi(b[2] - a[2] - theta_ab_);
	if (jacobians)
	{
		if (double* J = jacobians[0])  // row-major 3×3
		{
			J[0] = -c, J[1] = -s, J[2] = -s * dx + c * dy;
			J[3] = s, J[4] = -c, J[5] = -c * dx - s * dy;
			J[6] = 0, J[7] = 0, J[8] = -1;
		}
		if (double* J = jacobians[1])
		{
			J[0] = c, J[1] = s, J[2] = 0;
			J[3] = -s, J[4] = c, J[5] = 0;
			J[6] = 0, J[7] = 0, J[8] = 1;
		}
	}
	return true;
}

PosePrior2dFactor::PosePrior2dFactor(double x0, double y0, double theta0)
	: Factor(3, {3}), p0_(x0, y0), theta0_(theta0)
{
}

bool PosePrior2dFactor::evaluate(const double* const* x, double* residual, double* const* jacobians) const
{
	const double c = std::cos(theta0_), s = std::sin(theta0_);
	const double dx = x[0][0] - p0_.x(), dy = x[0][1] - p0_.y();
	residual[0] = c * dx + s * dy;
	residual[1] = -s * dx + c * dy;
	residual[2] = wrap_to_pi(x[0][2] - theta0_);
	if (jacobians && jacobians[0])
	{
		double* J = jacobians[0];
		J[0] = c, J[1] = s, J[2] = 0;
		J[3] = -s, J[4] = c, J[5] = 0;
		J[6] = 0, J[7] = 0, J[8] = 1;
	}
	return true;
}
}  // namespace swba
