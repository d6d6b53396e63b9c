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

/** The row-major 6×6 Jacobian [A 0; 0 B]: translation rows on the position, rotation rows on the
 * rotation, no cross terms. */
void write_block_diagonal(const Mat33& A, const Mat33& B, double* jacobian)
{
	Eigen::Map<Mat66> J(jacobian);
	J.topLeftCorner<3, 3>() = A;
	J.topRightCorner<3, 3>().setZero();
	J.bottomLeftCorner<3, 3>().setZero();
	J.bottomRightCorner<3, 3>() = B;
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
		if (jacobians[1]) write_block_diagonal(Rab_est, d_rot_b, jacobians[1]);
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
	if (jacobians && jacobians[0]) write_block_diagonal(R0T_R, d_twice_vec_d_right_rotation(q_err), jacobians[0]);
	return true;
}

Pose2dErrorFactor::Pose2dErrorFactor(const Eigen::Vector3d& z) : Factor(3, {3, 3}), z_(z), fixed_a_(0, 0, 0) {}

Pose2dErrorFactor::Pose2dErrorFactor(const Eigen::Vector3d& z, const Eigen::Vector3d& fixed_a)
	: Factor(3, {3}), z_(z), fixed_a_(fixed_a)
{
}

bool Pose2dErrorFactor::evaluate(const double* const* x, double* residual, double* const* jacobians) const
{
	const bool unary = num_variables() == 1;
	const double* a = unary ? fixed_a_.data() : x[0];
	const double* b = unary ? x[0] : x[1];
	double* J_a = jacobians && !unary ? jacobians[0] : nullptr;  // row-major 3×3
	double* J_b = jacobians ? jacobians[unary ? 0 : 1] : nullptr;
	const double c = std::cos(a[2]), s = std::sin(a[2]);
	const double dx = b[0] - a[0], dy = b[1] - a[1];
	// R(θ_a)ᵀ·(p_b − p_a)
	residual[0] = c * dx + s * dy - z_.x();
	residual[1] = -s * dx + c * dy - z_.y();
	residual[2] = wrap_to_pi(b[2] - a[2] - z_.z());
	if (J_a)
	{
		J_a[0] = -c, J_a[1] = -s, J_a[2] = -s * dx + c * dy;
		J_a[3] = s, J_a[4] = -c, J_a[5] = -c * dx - s * dy;
		J_a[6] = 0, J_a[7] = 0, J_a[8] = -1;
	}
	if (J_b)
	{
		J_b[0] = c, J_b[1] = s, J_b[2] = 0;
		J_b[3] = -s, J_b[4] = c, J_b[5] = 0;
		J_b[6] = 0, J_b[7] = 0, J_b[8] = 1;
	}
	return true;
}

RelativePose2dFactor::RelativePose2dFactor(double x_ab, double y_ab, double theta_ab)
	: Pose2dErrorFactor(Eigen::Vector3d(x_ab, y_ab, theta_ab))
{
}

PosePrior2dFactor::PosePrior2dFactor(double x0, double y0, double theta0)
	: Pose2dErrorFactor(Eigen::Vector3d::Zero(), Eigen::Vector3d(x0, y0, theta0))
{
}
}  // namespace swba
