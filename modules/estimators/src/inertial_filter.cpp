#include <swba/estimators/inertial_filter.h>

#include <swba/core/lie.h>
#include <swba/core/manifold.h>
#include <swba/core/validation.h>
#include <swba/factors/between_pose.h>
#include <swba/factors/pose_prior.h>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace swba::estimators
{
namespace
{
using Matrix15d = Eigen::Matrix<double, 15, 15>;
using RowMajor6 = Eigen::Matrix<double, 6, 6, Eigen::RowMajor>;

Eigen::Vector3d position(const mrpt::poses::CPose3D& p) { return {p.x(), p.y(), p.z()}; }

/** blockdiag(R, I): maps the manifold tangent [ρ (body), ω] to the filter's [δp (world), δφ]. */
Matrix6d body_to_world(const Eigen::Matrix3d& R)
{
	Matrix6d A = Matrix6d::Identity();
	A.topLeftCorner<3, 3>() = R;
	return A;
}

/** Evaluates a pose factor at the given poses; returns the residual and the manifold Jacobians. */
Eigen::Matrix<double, 6, 1> evaluate_pose_factor(const Factor& f, const std::vector<const double*>& x, RowMajor6* Ji,
												 RowMajor6* Jj)
{
	Eigen::Matrix<double, 6, 1> r;
	double* jac[2] = {Ji ? Ji->data() : nullptr, Jj ? Jj->data() : nullptr};
	if (!f.evaluate(x.data(), r.data(), jac)) throw std::runtime_error("inertial filter: pose residual not finite");
	return r;
}
}  // namespace

InertialInput inertial_input(const io::ObservationRawlog& log)
{
	InertialInput in;
	for (const auto& r : log.imu) in.imu.push_back({r.t, r.acc, r.gyro});
	in.pose_priors = log.pose_priors;
	in.odometry = log.odometry;
	return in;
}

void InertialPriorOptions::validate() const
{
	for (double s : {velocity_sigma, velocity_sigma_unknown, accel_bias_sigma, gyro_bias_sigma, odometry_pose_sigma,
					 odometry_tilt_sigma})
		if (!(std::isfinite(s) && s > 0)) throw std::invalid_argument("initial-state sigmas must be positive");
}

InertialInitialState initial_inertial_state(const InertialInput& in, const InertialPriorOptions& o)
{
	if (in.imu.size() < 2) throw std::invalid_argument("inertial input: fewer than two IMU readings");
	if (in.pose_priors.empty() && in.odometry.empty()) throw std::invalid_argument("inertial input: no pose to start from");
	InertialInitialState s;
	Matrix6d pose_cov;
	if (!in.pose_priors.empty())
	{
		s.t = in.pose_priors.front().t;
		s.x.R = in.pose_priors.front().pose.getRotationMatrix().asEigen();
		s.x.p = position(in.pose_priors.front().pose);
		pose_cov = in.pose_priors.front().covariance;
	}
	else
	{
		s.t = in.odometry.front().t;
		s.x.R = in.odometry.front().pose.getRotationMatrix().asEigen();
		s.x.p = position(in.odometry.front().pose);
		// In the tangent [ρ (body), ω (body)]: position and yaw tight, tilt loose, the rotation's world-axis
		// covariance diag(σ_tilt², σ_tilt², σ²) moved to the body axes (ω_world = R ω).
		const double sp = o.odometry_pose_sigma, st = o.odometry_tilt_sigma;
		pose_cov.setZero();
		pose_cov.topLeftCorner<3, 3>() = Eigen::Matrix3d::Identity() * sp * sp;
		pose_cov.bottomRightCorner<3, 3>() =
			s.x.R.transpose() * Eigen::Vector3d(st * st, st * st, sp * sp).asDiagonal() * s.x.R;
	}
	if (s.t < in.imu.front().t) throw std::invalid_argument("inertial input: the first pose precedes the first IMU reading");
	double sv = o.velocity_sigma_unknown;
	if (in.odometry.size() >= 2 && in.odometry[1].t > in.odometry[0].t)
	{
		const mrpt::poses::CPose3D D = in.odometry[1].pose - in.odometry[0].pose;
		s.x.v = s.x.R * (position(D) / (in.odometry[1].t - in.odometry[0].t));
		sv = o.velocity_sigma;
	}
	s.P.setZero();
	const Matrix6d A = body_to_world(s.x.R);
	s.P.topLeftCorner<6, 6>() = A * pose_cov * A.transpose();
	s.P.block<3, 3>(6, 6) = Eigen::Matrix3d::Identity() * sv * sv;
	s.P.block<3, 3>(9, 9) = Eigen::Matrix3d::Identity() * o.accel_bias_sigma * o.accel_bias_sigma;
	s.P.block<3, 3>(12, 12) = Eigen::Matrix3d::Identity() * o.gyro_bias_sigma * o.gyro_bias_sigma;
	return s;
}

ErrorStateKalmanFilter::ErrorStateKalmanFilter(const ImuNoise& noise, const InertialInitialState& init)
	: noise_(noise), t_(init.t), x_(init.x), b_(init.bias), P_(init.P)
{
	validate_with_prefix(noise_, "ErrorStateKalmanFilter: ");
}

void ErrorStateKalmanFilter::propagate(const ImuSample& s0, const ImuSample& s1)
{
	const double dt = s1.t - s0.t;
	if (dt <= 0) return;
	const MidpointLinearization L = midpoint_linearization(x_.R, s0, s1, b_);
	x_ = imu_midpoint_step(x_, s0, s1, b_, noise_.gravity);
	const Eigen::MatrixXd P15 = P_.topLeftCorner<15, 15>();
	P_.topLeftCorner<15, 15>() = L.F * P15 * L.F.transpose() + L.G * imu_step_noise(noise_, dt) * L.G.transpose();
	if (P_.rows() > 15)
	{
		P_.topRightCorner(15, 6) = L.F * P_.topRightCorner(15, 6);
		P_.bottomLeftCorner(6, 15) = P_.topRightCorner(15, 6).transpose();
	}
	t_ = s1.t;
}

mrpt::poses::CPose3D ErrorStateKalmanFilter::pose() const { return SE3Manifold::to_pose(x_.R, x_.p); }

Matrix6d ErrorStateKalmanFilter::pose_covariance() const
{
	const Matrix6d A = body_to_world(x_.R.transpose());
	return A * P_.topLeftCorner<6, 6>() * A.transpose();
}

double ErrorStateKalmanFilter::update(const Eigen::Matrix<double, 6, 1>& r, const Eigen::MatrixXd& H,
									  const Matrix6d& covariance)
{
	const Eigen::MatrixXd PHt = P_ * H.transpose();
	const Matrix6d S = H * PHt + covariance;
	const Eigen::LDLT<Matrix6d> ldlt(S);
	const Eigen::MatrixXd K = ldlt.solve(PHt.transpose()).transpose();
	const Eigen::MatrixXd IKH = Eigen::MatrixXd::Identity(P_.rows(), P_.cols()) - K * H;
	P_ = IKH * P_ * IKH.transpose() + K * covariance * K.transpose();
	inject(-K * r);
	return r.dot(ldlt.solve(r));
}

void ErrorStateKalmanFilter::inject(const Eigen::VectorXd& dx)
{
	x_.p += dx.segment<3>(0);
	x_.R = Eigen::Quaterniond(x_.R * so3_exp(dx.segment<3>(3))).normalized().toRotationMatrix();
	x_.v += dx.segment<3>(6);
	b_ += dx.segment<6>(9);
	// Reset: the attitude errors are re-expressed about the corrected attitudes, δφ' ≈ (I − ½[δφ̂]×) δφ.
	Eigen::MatrixXd G = Eigen::MatrixXd::Identity(P_.rows(), P_.cols());
	G.block<3, 3>(3, 3) -= 0.5 * skew(dx.segment<3>(3));
	if (clone_)
	{
		clone_->p += dx.segment<3>(15);
		clone_->R = Eigen::Quaterniond(clone_->R * so3_exp(dx.segment<3>(18))).normalized().toRotationMatrix();
		G.block<3, 3>(18, 18) -= 0.5 * skew(dx.segment<3>(18));
	}
	P_ = G * P_ * G.transpose();
	P_ = 0.5 * (P_ + P_.transpose()).eval();
}

double ErrorStateKalmanFilter::update_pose(const mrpt::poses::CPose3D& Z, const Matrix6d& covariance)
{
	double T[12];
	SE3Manifold::from_pose(pose(), T);
	const PosePriorFactor f(Z);
	RowMajor6 J;
	const Eigen::Matrix<double, 6, 1> r = evaluate_pose_factor(f, {T}, &J, nullptr);
	Eigen::MatrixXd H = Eigen::MatrixXd::Zero(6, P_.rows());
	H.leftCols<6>() = J * body_to_world(x_.R.transpose());
	return update(r, H, covariance);
}

void ErrorStateKalmanFilter::clone_pose()
{
	const Matrix15d P15 = P_.topLeftCorner<15, 15>();
	P_.setZero(21, 21);
	P_.topLeftCorner<15, 15>() = P15;
	P_.topRightCorner<15, 6>() = P15.leftCols<6>();
	P_.bottomLeftCorner<6, 15>() = P15.topRows<6>();
	P_.bottomRightCorner<6, 6>() = P15.topLeftCorner<6, 6>();
	clone_ = Clone{x_.R, x_.p};
}

double ErrorStateKalmanFilter::update_relative(const mrpt::poses::CPose3D& D, const Matrix6d& covariance)
{
	if (!clone_) throw std::logic_error("ErrorStateKalmanFilter::update_relative without a cloned pose");
	double Ti[12], Tj[12];
	SE3Manifold::from_pose(SE3Manifold::to_pose(clone_->R, clone_->p), Ti);
	SE3Manifold::from_pose(pose(), Tj);
	const BetweenPoseFactor f(D);
	RowMajor6 Ji, Jj;
	const Eigen::Matrix<double, 6, 1> r = evaluate_pose_factor(f, {Ti, Tj}, &Ji, &Jj);
	Eigen::MatrixXd H = Eigen::MatrixXd::Zero(6, P_.rows());
	H.leftCols<6>() = Jj * body_to_world(x_.R.transpose());
	H.rightCols<6>() = Ji * body_to_world(clone_->R.transpose());
	const double nis = update(r, H, covariance);
	const Matrix15d P15 = P_.topLeftCorner<15, 15>();
	P_ = P15;
	clone_.reset();
	return nis;
}
}  // namespace swba::estimators
