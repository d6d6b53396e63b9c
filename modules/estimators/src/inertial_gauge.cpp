#include "inertial_gauge.h"

#include <swba/core/lie.h>
#include <swba/factors/pose_prior.h>

#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>

namespace swba::estimators::detail
{
namespace
{
using RowMajorJ = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

double wrapped(double a) { return std::atan2(std::sin(a), std::cos(a)); }

std::vector<int> tilt_dims(const Factor& inner, int held)
{
	if (held < 0 || held >= inner.num_variables() || inner.tangent_dims()[held] != SE3Manifold::kTangent)
		throw std::invalid_argument("TiltFactor: the held variable must be an SE(3) pose of the inner factor");
	std::vector<int> dims = inner.tangent_dims();
	dims[held] = 2;
	return dims;
}

Eigen::Matrix3d rz(double w) { return Eigen::AngleAxisd(w, Eigen::Vector3d::UnitZ()).toRotationMatrix(); }
}  // namespace

void TiltManifold::plus(const double* x, const double* delta, double* x_plus) const
{
	const mrpt::poses::CPose3D T = SE3Manifold::to_pose(x);
	SE3Manifold::from_pose(
		mrpt::poses::CPose3D(T.x(), T.y(), T.z(), T.yaw(), T.pitch() + delta[0], T.roll() + delta[1]), x_plus);
}

void TiltManifold::minus(const double* y, const double* x, double* delta) const
{
	const mrpt::poses::CPose3D Ty = SE3Manifold::to_pose(y), Tx = SE3Manifold::to_pose(x);
	delta[0] = wrapped(Ty.pitch() - Tx.pitch());
	delta[1] = wrapped(Ty.roll() - Tx.roll());
}

std::shared_ptr<const TiltManifold> TiltManifold::instance()
{
	static const auto m = std::make_shared<const TiltManifold>();
	return m;
}

Eigen::Matrix<double, 6, 2> TiltManifold::basis(const double* x)
{
	// R = Rz(ψ)Ry(θ)Rx(φ): a roll update is R·Exp(e_x δφ); a pitch update Rz Ry(θ+δθ) Rx = R·Exp(Rxᵀe_y δθ).
	const double roll = SE3Manifold::to_pose(x).roll();
	Eigen::Matrix<double, 6, 2> E = Eigen::Matrix<double, 6, 2>::Zero();
	E.block<3, 1>(3, 0) = Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()).toRotationMatrix().transpose().col(1);
	E.block<3, 1>(3, 1) = Eigen::Vector3d::UnitX();
	return E;
}

TiltFactor::TiltFactor(std::shared_ptr<const Factor> inner, int held)
	: Factor(inner->residual_dim(), tilt_dims(*inner, held)), inner_(std::move(inner)), held_(held)
{
	if (inner_->has_sqrt_information()) set_sqrt_information(inner_->sqrt_information());
}

bool TiltFactor::evaluate(const double* const* x, double* residual, double* const* jacobians) const
{
	const int m = residual_dim();
	RowMajorJ J6(m, SE3Manifold::kTangent);
	std::vector<double*> inner_jac(static_cast<std::size_t>(num_variables()), nullptr);
	if (jacobians)
		for (int i = 0; i < num_variables(); i++) inner_jac[i] = i == held_ ? J6.data() : jacobians[i];
	const bool want_held = jacobians && jacobians[held_];
	if (!want_held) inner_jac[held_] = nullptr;
	if (!inner_->evaluate(x, residual, jacobians ? inner_jac.data() : nullptr)) return false;
	if (want_held) Eigen::Map<RowMajorJ>(jacobians[held_], m, 2) = J6 * TiltManifold::basis(x[held_]);
	return true;
}

Eigen::Matrix<double, 6, 6> tilt_prior_sqrt_information(const Eigen::Matrix3d& R_Z, double tilt_sigma)
{
	// The residual's rotation rows are the body-frame error ω of Z; R_Z·ω is the world's. Rows x and y of
	// that, over σ; the position rows and the world-yaw row stay zero.
	Eigen::Matrix<double, 6, 6> W = Eigen::Matrix<double, 6, 6>::Zero();
	W.block<2, 3>(3, 3) = R_Z.topRows<2>() / tilt_sigma;
	return W;
}

std::shared_ptr<Factor> inertial_gauge_anchor(const InertialGaugeReference& at)
{
	// Stiff, so that LM cannot move the four directions; the value does not matter otherwise, since the
	// rest of the window has no information along them (the residual stays at zero).
	constexpr double kSigma = 1e-6;
	const double* Z = at.pose.data();
	const Eigen::Matrix3d R_Z = se3_view(Z).leftCols<3>();
	// The residual is [R_Zᵀ(p − p_Z), ω] in Z's body frame: R_Z maps both to the world's axes.
	Eigen::Matrix<double, 6, 6> W = Eigen::Matrix<double, 6, 6>::Zero();
	W.topLeftCorner<3, 3>() = R_Z / kSigma;
	W.block<1, 3>(5, 3) = R_Z.row(2) / kSigma;
	auto f = std::make_shared<PosePriorFactor>(SE3Manifold::to_pose(Z));
	f->set_sqrt_information(W);
	return f;
}

void hold_inertial_gauge(Problem& problem, const InertialGaugeReference& at,
						 const std::vector<std::pair<VariableId, VariableId>>& window)
{
	if (at.id < 0) return;
	const mrpt::poses::CPose3D was = SE3Manifold::to_pose(at.pose.data()),
							   now = SE3Manifold::to_pose(problem.value(at.id));
	const Eigen::Matrix3d R = rz(-wrapped(now.yaw() - was.yaw()));
	const Eigen::Vector3d u = R * Eigen::Vector3d(now.x(), now.y(), now.z()) - Eigen::Vector3d(was.x(), was.y(), was.z());
	for (const auto& [Tid, vid] : window)
	{
		if (problem.variable(Tid).constant) continue;
		std::vector<double> x(problem.value(Tid), problem.value(Tid) + SE3Manifold::kAmbient);
		auto T = se3_view(x.data());
		T.leftCols<3>() = R * T.leftCols<3>().eval();
		T.col(3) = R * T.col(3).eval() - u;
		problem.set_value(Tid, x.data());
		if (vid < 0) continue;
		const Eigen::Vector3d v = R * Eigen::Map<const Eigen::Vector3d>(problem.value(vid));
		problem.set_value(vid, v.data());
	}
}
}  // namespace swba::estimators::detail
