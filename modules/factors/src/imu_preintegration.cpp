#include <swba/factors/imu_preintegration.h>

#include <swba/core/lie.h>
#include <swba/core/validation.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace swba
{
void ImuNoise::validate() const
{
	for (double x : {accel_noise_density, gyro_noise_density, accel_random_walk, gyro_random_walk})
		if (!(std::isfinite(x) && x > 0))
			throw std::invalid_argument("IMU noise densities and random walks must be positive");
	if (!gravity.allFinite()) throw std::invalid_argument("gravity must be finite");
}

IniKeys<ImuNoise> ImuNoise::ini_keys(const std::string& section)
{
	using O = ImuNoise;
	using namespace ini;
	// The four densities, each > 0 as validate() requires.
	const auto density = [&section](const char* key, const char* unit, const char* meaning, double O::*field) {
		return number_key<O>(section, key, unit, meaning, field, parse_positive);
	};
	return {
		density("accel_noise_density", "m/s^2/sqrt(Hz)", "accelerometer white noise density", &O::accel_noise_density),
		density("gyro_noise_density", "rad/s/sqrt(Hz)", "gyroscope white noise density", &O::gyro_noise_density),
		density("accel_random_walk", "m/s^3/sqrt(Hz)", "accelerometer bias random walk", &O::accel_random_walk),
		density("gyro_random_walk", "rad/s^2/sqrt(Hz)", "gyroscope bias random walk", &O::gyro_random_walk),
		{section, "gravity_z", "m/s^2", "gravity along the world z axis (negative: z up)",
		 [](const std::string& v, O& o) { o.gravity = Eigen::Vector3d(0, 0, parse_double(v)); },
		 [](const O& o) { return format_double(o.gravity.z()); }},
	};
}

ImuSample interpolate_imu(const ImuSample& a, const ImuSample& b, double t)
{
	if (b.t <= a.t) return a;
	const double s = std::clamp((t - a.t) / (b.t - a.t), 0.0, 1.0);
	ImuSample out;
	out.t = a.t + s * (b.t - a.t);
	out.acc = (1 - s) * a.acc + s * b.acc;
	out.gyro = (1 - s) * a.gyro + s * b.gyro;
	return out;
}

namespace
{
Eigen::Matrix3d normalized_rotation(const Eigen::Matrix3d& R) { return Eigen::Quaterniond(R).normalized().toRotationMatrix(); }
}  // namespace

NavState imu_midpoint_step(const NavState& x, const ImuSample& s0, const ImuSample& s1, const Vector6d& bias,
						   const Eigen::Vector3d& gravity)
{
	const double dt = s1.t - s0.t;
	const Eigen::Vector3d w = 0.5 * (s0.gyro + s1.gyro) - bias.tail<3>();
	NavState y;
	y.R = normalized_rotation(x.R * so3_exp(w * dt));
	const Eigen::Vector3d a = 0.5 * (x.R * (s0.acc - bias.head<3>()) + y.R * (s1.acc - bias.head<3>())) + gravity;
	y.p = x.p + x.v * dt + 0.5 * a * dt * dt;
	y.v = x.v + a * dt;
	return y;
}

MidpointLinearization midpoint_linearization(const Eigen::Matrix3d& R0, const ImuSample& s0, const ImuSample& s1,
											 const Vector6d& bias)
{
	const double dt = s1.t - s0.t;
	const Eigen::Vector3d theta = (0.5 * (s0.gyro + s1.gyro) - bias.tail<3>()) * dt;
	MidpointLinearization L;
	L.dR = so3_exp(theta);
	const Eigen::Matrix3d R1 = R0 * L.dR;
	const Eigen::Matrix3d Jr = so3_right_jacobian(theta);
	const Eigen::Vector3d a0 = s0.acc - bias.head<3>(), a1 = s1.acc - bias.head<3>();
	// ∂ā/∂δφ_k (the step's start error, through both readings), ∂ā/∂δb_a and ∂ā/∂δb_g.
	const Eigen::Matrix3d M_phi = -0.5 * R0 * skew(a0) - 0.5 * R1 * skew(a1) * L.dR.transpose();
	const Eigen::Matrix3d M_a = -0.5 * (R0 + R1);
	const Eigen::Matrix3d M_g = 0.5 * R1 * skew(a1) * Jr * dt;
	const double h = 0.5 * dt * dt;
	const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
	L.F.setIdentity();
	L.F.block<3, 3>(0, 3) = h * M_phi;
	L.F.block<3, 3>(0, 6) = dt * I;
	L.F.block<3, 3>(0, 9) = h * M_a;
	L.F.block<3, 3>(0, 12) = h * M_g;
	L.F.block<3, 3>(3, 3) = L.dR.transpose();
	L.F.block<3, 3>(3, 12) = -Jr * dt;
	L.F.block<3, 3>(6, 3) = dt * M_phi;
	L.F.block<3, 3>(6, 9) = dt * M_a;
	L.F.block<3, 3>(6, 12) = dt * M_g;
	L.G.setZero();
	L.G.block<3, 3>(0, 0) = h * M_a;
	L.G.block<3, 3>(0, 3) = h * M_g;
	L.G.block<3, 3>(3, 3) = -Jr * dt;
	L.G.block<3, 3>(6, 0) = dt * M_a;
	L.G.block<3, 3>(6, 3) = dt * M_g;
	L.G.block<6, 6>(9, 6).setIdentity();
	return L;
}

Eigen::Matrix<double, 12, 12> imu_step_noise(const ImuNoise& n, double dt)
{
	Eigen::Matrix<double, 12, 1> d;
	d << Eigen::Vector3d::Constant(n.accel_noise_density * n.accel_noise_density / dt),
		Eigen::Vector3d::Constant(n.gyro_noise_density * n.gyro_noise_density / dt),
		Eigen::Vector3d::Constant(n.accel_random_walk * n.accel_random_walk * dt),
		Eigen::Vector3d::Constant(n.gyro_random_walk * n.gyro_random_walk * dt);
	return d.asDiagonal();
}

ImuPreintegration::ImuPreintegration(const ImuNoise& noise, const Vector6d& linearization_bias)
	: noise_(noise), bias_lin_(linearization_bias)
{
	validate_with_prefix(noise_, "ImuPreintegration: ");
	reset_integration();
}

void ImuPreintegration::reset_integration()
{
	dt_sum_ = 0;
	dR_.setIdentity();
	dv_.setZero();
	dp_.setZero();
	J_bias_.setZero();
	cov_.setZero();
}

void ImuPreintegration::add_sample(const ImuSample& s)
{
	if (!samples_.empty() && s.t < samples_.back().t)
		throw std::invalid_argument("ImuPreintegration: readings out of time order");
	if (!samples_.empty()) integrate_step(samples_.back(), s);
	samples_.push_back(s);
}

void ImuPreintegration::reintegrate(const Vector6d& linearization_bias)
{
	bias_lin_ = linearization_bias;
	reset_integration();
	for (size_t k = 1; k < samples_.size(); k++) integrate_step(samples_[k - 1], samples_[k]);
}

void ImuPreintegration::integrate_step(const ImuSample& s0, const ImuSample& s1)
{
	const double dt = s1.t - s0.t;
	if (dt <= 0) return;  // a repeated reading adds nothing
	const MidpointLinearization L = midpoint_linearization(dR_, s0, s1, bias_lin_);
	const Eigen::Matrix3d R1 = normalized_rotation(dR_ * L.dR);
	const Eigen::Vector3d a = 0.5 * (dR_ * (s0.acc - bias_lin_.head<3>()) + R1 * (s1.acc - bias_lin_.head<3>()));
	dp_ += dv_ * dt + 0.5 * a * dt * dt;
	dv_ += a * dt;
	dR_ = R1;
	// The bias Jacobians follow the error transition: J ← F_ηη J + F_ηb (η = [δp, δφ, δv]).
	J_bias_ = L.F.topLeftCorner<9, 9>() * J_bias_ + L.F.topRightCorner<9, 6>();
	cov_ = L.F * cov_ * L.F.transpose() + L.G * imu_step_noise(noise_, dt) * L.G.transpose();
	dt_sum_ += dt;
}

Eigen::Matrix3d ImuPreintegration::corrected_delta_R(const Vector6d& bias) const
{
	const Vector6d db = bias - bias_lin_;
	return dR_ * so3_exp(J_bias_.block<3, 3>(3, 3) * db.tail<3>());
}

Eigen::Vector3d ImuPreintegration::corrected_delta_v(const Vector6d& bias) const
{
	return dv_ + J_bias_.block<3, 6>(6, 0) * (bias - bias_lin_);
}

Eigen::Vector3d ImuPreintegration::corrected_delta_p(const Vector6d& bias) const
{
	return dp_ + J_bias_.block<3, 6>(0, 0) * (bias - bias_lin_);
}

NavState ImuPreintegration::predict(const NavState& xi, const Vector6d& bias_i) const
{
	const double T = dt_sum_;
	const Eigen::Vector3d& g = noise_.gravity;
	NavState xj;
	xj.R = normalized_rotation(xi.R * corrected_delta_R(bias_i));
	xj.v = xi.v + g * T + xi.R * corrected_delta_v(bias_i);
	xj.p = xi.p + xi.v * T + 0.5 * g * T * T + xi.R * corrected_delta_p(bias_i);
	return xj;
}

bool ImuPreintegration::bias_far(const Vector6d& bias, double accel_threshold, double gyro_threshold) const
{
	const Vector6d db = bias - bias_lin_;
	return db.head<3>().cwiseAbs().maxCoeff() > accel_threshold || db.tail<3>().cwiseAbs().maxCoeff() > gyro_threshold;
}
}  // namespace swba
