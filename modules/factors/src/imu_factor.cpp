#include <swba/factors/imu_factor.h>

#include <swba/core/lie.h>
#include <swba/core/manifold.h>

#include <Eigen/Cholesky>
#include <stdexcept>

namespace swba
{
namespace
{
using Jac15x6 = Eigen::Matrix<double, 15, 6, Eigen::RowMajor>;
using Jac15x3 = Eigen::Matrix<double, 15, 3, Eigen::RowMajor>;
}  // namespace

ImuPreintegrationFactor::ImuPreintegrationFactor(std::shared_ptr<const ImuPreintegration> preintegration)
	: Factor(15, {SE3Manifold::kTangent, 3, 6, SE3Manifold::kTangent, 3, 6}), pim_(std::move(preintegration))
{
	if (!pim_ || !(pim_->delta_t() > 0))
		throw std::invalid_argument("ImuPreintegrationFactor: the pre-integration spans no time");
	// Whitening W = L⁻¹ with Σ = L·Lᵀ, so that ‖W r‖² = rᵀ Σ⁻¹ r without forming Σ⁻¹.
	const Eigen::LLT<Matrix15d> llt(pim_->covariance());
	if (llt.info() != Eigen::Success)
		throw std::invalid_argument(
			"ImuPreintegrationFactor: covariance not positive definite (fewer than two integration steps?)");
	const Matrix15d L = llt.matrixL();
	set_sqrt_information(L.triangularView<Eigen::Lower>().solve(Matrix15d::Identity()));
}

namespace
{
/** What the Jacobians of the IMU residual are built from (see evaluate()). */
struct ImuResidualParts
{
	Eigen::Matrix3d Ri, Rj, E;		   ///< rotations of i and j, E = ΔR̃ᵀ R_iᵀ R_j
	Eigen::Vector3d dp, dv, phi_b, rR;  ///< R_iᵀ(position / velocity terms), J_Rg δb_g, Log(E)
	double T = 0;					   ///< Δt
};

void write_imu_jacobians(const ImuResidualParts& q, const Eigen::Matrix<double, 9, 6>& J, double* const* jacobians)
{
	const Eigen::Matrix3d Jr_inv = so3_right_jacobian_inverse(q.rR);
	const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
	if (jacobians[0])  // δT_i = [ρ_i, ω_i]: p_i += R_i ρ_i, R_i ← R_i Exp(ω_i)
	{
		Eigen::Map<Jac15x6> D(jacobians[0]);
		D.setZero();
		D.block<3, 3>(0, 0) = -I;
		D.block<3, 3>(0, 3) = skew(q.dp);
		D.block<3, 3>(3, 3) = -Jr_inv * q.Rj.transpose() * q.Ri;
		D.block<3, 3>(6, 3) = skew(q.dv);
	}
	if (jacobians[1])
	{
		Eigen::Map<Jac15x3> D(jacobians[1]);
		D.setZero();
		D.block<3, 3>(0, 0) = -q.Ri.transpose() * q.T;
		D.block<3, 3>(6, 0) = -q.Ri.transpose();
	}
	if (jacobians[2])  // b_i: first-order correction of the deltas, and the random walk
	{
		Eigen::Map<Jac15x6> D(jacobians[2]);
		D.setZero();
		D.block<3, 6>(0, 0) = -J.block<3, 6>(0, 0);
		// ΔR̃(b_g + δ) ≈ ΔR̃·Exp(J_r(φ_b) J_Rg δ), so E ← Exp(−J_r J_Rg δ)·E = E·Exp(−Eᵀ J_r J_Rg δ).
		D.block<3, 3>(3, 3) = -Jr_inv * q.E.transpose() * so3_right_jacobian(q.phi_b) * J.block<3, 3>(3, 3);
		D.block<3, 6>(6, 0) = -J.block<3, 6>(6, 0);
		D.block<6, 6>(9, 0) = -Eigen::Matrix<double, 6, 6>::Identity();
	}
	if (jacobians[3])
	{
		Eigen::Map<Jac15x6> D(jacobians[3]);
		D.setZero();
		D.block<3, 3>(0, 0) = q.Ri.transpose() * q.Rj;
		D.block<3, 3>(3, 3) = Jr_inv;
	}
	if (jacobians[4])
	{
		Eigen::Map<Jac15x3> D(jacobians[4]);
		D.setZero();
		D.block<3, 3>(6, 0) = q.Ri.transpose();
	}
	if (jacobians[5])
	{
		Eigen::Map<Jac15x6> D(jacobians[5]);
		D.setZero();
		D.block<6, 6>(9, 0).setIdentity();
	}
}
}  // namespace

bool ImuPreintegrationFactor::evaluate(const double* const* x, double* residual, double* const* jacobians) const
{
	const auto Ti = se3_view(x[0]);
	const auto Tj = se3_view(x[3]);
	const Eigen::Map<const Eigen::Vector3d> vi(x[1]), vj(x[4]);
	const Eigen::Map<const Vector6d> bi(x[2]), bj(x[5]);
	const ImuPreintegration& m = *pim_;
	const Eigen::Vector3d& g = m.noise().gravity;
	const Eigen::Matrix<double, 9, 6>& J = m.bias_jacobian();
	const Vector6d db = bi - m.linearization_bias();
	ImuResidualParts q;
	q.Ri = Ti.leftCols<3>();
	q.Rj = Tj.leftCols<3>();
	q.T = m.delta_t();
	q.dp = q.Ri.transpose() * (Tj.col(3) - Ti.col(3) - vi * q.T - 0.5 * g * q.T * q.T);
	q.dv = q.Ri.transpose() * (vj - vi - g * q.T);
	q.phi_b = J.block<3, 3>(3, 3) * db.tail<3>();
	q.E = (m.delta_R() * so3_exp(q.phi_b)).transpose() * q.Ri.transpose() * q.Rj;
	q.rR = so3_log(q.E);

	Eigen::Map<Eigen::Matrix<double, 15, 1>> r(residual);
	r.segment<3>(0) = q.dp - (m.delta_p() + J.block<3, 6>(0, 0) * db);
	r.segment<3>(3) = q.rR;
	r.segment<3>(6) = q.dv - (m.delta_v() + J.block<3, 6>(6, 0) * db);
	r.segment<6>(9) = bj - bi;
	if (!r.allFinite()) return false;
	if (jacobians) write_imu_jacobians(q, J, jacobians);
	return true;
}

EuclideanPriorFactor::EuclideanPriorFactor(const Eigen::VectorXd& mean)
	: Factor(static_cast<int>(mean.size()), {static_cast<int>(mean.size())}), mean_(mean)
{
	if (mean.size() == 0) throw std::invalid_argument("EuclideanPriorFactor: empty mean");
}

bool EuclideanPriorFactor::evaluate(const double* const* x, double* residual, double* const* jacobians) const
{
	const int n = static_cast<int>(mean_.size());
	const Eigen::Map<const Eigen::VectorXd> xv(x[0], n);
	Eigen::Map<Eigen::VectorXd>(residual, n) = xv - mean_;
	if (jacobians && jacobians[0])
		Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(jacobians[0], n, n)
			.setIdentity();
	return true;
}
}  // namespace swba
