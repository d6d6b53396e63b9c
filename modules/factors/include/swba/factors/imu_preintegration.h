/** \file imu_preintegration.h
 * IMU model, midpoint integration and on-manifold pre-integration (Forster et al., TRO 2017) with
 * first-order bias correction and covariance propagated from continuous-time noise densities.
 *
 * Conventions (shared with ImuPreintegrationFactor, the error-state Kalman filter and the simulator):
 *   - world frame with gravity `gravity` (default (0, 0, −9.81): z up); body pose T = [R | p] maps body
 *     to world; v is the body's velocity in the world frame;
 *   - an IMU sample is the specific force a = Rᵀ(p̈ − g) + b_a + n_a and the body rate ω + b_g + n_g, in
 *     the body frame; the bias vector is b = [b_a; b_g] ∈ ℝ⁶;
 *   - midpoint integration between samples k and k+1 (Δt = t_{k+1} − t_k):
 *       ω̄ = ½(ω_k + ω_{k+1}) − b_g,  R_{k+1} = R_k·Exp(ω̄ Δt),
 *       ā = ½(R_k(a_k − b_a) + R_{k+1}(a_{k+1} − b_a)) (+ g for the navigation state),
 *       p_{k+1} = p_k + v_k Δt + ½ ā Δt²,  v_{k+1} = v_k + ā Δt;
 *   - error state and residual order [p, R, v, b_a, b_g] (15); rotation errors are right (local):
 *     R_true = R·Exp(δφ). */
#pragma once

#include <swba/core/ini.h>

#include <Eigen/Core>
#include <string>
#include <vector>

namespace swba
{
using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix15d = Eigen::Matrix<double, 15, 15>;

/** Continuous-time IMU noise (white noise densities and bias random walks, as in a Kalibr / GTSAM
 * IMU configuration) and the world's gravity. A sample of rate 1/Δt then carries a discrete white noise
 * of variance σ²/Δt and a bias that moves by a variance σ_b²·Δt per sample. */
struct ImuNoise
{
	/** Accelerometer white noise density σ_a, m/s²/√Hz (Default = 0.019). */
	double accel_noise_density = 0.019;
	/** Gyroscope white noise density σ_g, rad/s/√Hz (Default = 0.015). */
	double gyro_noise_density = 0.015;
	/** Accelerometer bias random walk σ_ba, m/s³/√Hz (Default = 1e-4). */
	double accel_random_walk = 1e-4;
	/** Gyroscope bias random walk σ_bg, rad/s²/√Hz (Default = 1e-5). */
	double gyro_random_walk = 1e-5;
	/** Gravity in the world frame, m/s² (Default = (0, 0, −9.81)). */
	Eigen::Vector3d gravity{0.0, 0.0, -9.81};

	/** Throws std::invalid_argument unless all densities are positive and finite and gravity is finite. */
	void validate() const;
	/** Keys accel_noise_density, gyro_noise_density, accel_random_walk, gyro_random_walk, gravity_z. */
	static IniKeys<ImuNoise> ini_keys(const std::string& section);
};

/** One IMU reading: time (s), specific force (m/s², body) and angular rate (rad/s, body). */
struct ImuSample
{
	double t = 0;
	Eigen::Vector3d acc = Eigen::Vector3d::Zero();
	Eigen::Vector3d gyro = Eigen::Vector3d::Zero();
};

/** The reading at time t between two readings, linearly interpolated (t clamped to [a.t, b.t]). */
ImuSample interpolate_imu(const ImuSample& a, const ImuSample& b, double t);

/** Body navigation state: pose (R, p) and world velocity v. */
struct NavState
{
	Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
	Eigen::Vector3d p = Eigen::Vector3d::Zero();
	Eigen::Vector3d v = Eigen::Vector3d::Zero();
};

/** One midpoint step of the navigation state from reading s0 to reading s1 with bias b (see file). */
NavState imu_midpoint_step(const NavState& x, const ImuSample& s0, const ImuSample& s1, const Vector6d& bias,
						   const Eigen::Vector3d& gravity);

/** The quantities of one midpoint step shared by the pre-integration and the filter: the increment
 * θ = ω̄Δt, the bias-corrected readings and the linearised transition of the error [δp, δφ, δv, δb_a, δb_g]
 * (F, 15×15) and its noise input G (15×12, noise order [n_a, n_g, n_ba, n_bg]) for a step that starts at
 * rotation R0 (body to world, or to the pre-integration frame). */
struct MidpointLinearization
{
	Eigen::Matrix3d dR;	 ///< Exp(θ)
	Matrix15d F;
	Eigen::Matrix<double, 15, 12> G;
};
MidpointLinearization midpoint_linearization(const Eigen::Matrix3d& R0, const ImuSample& s0, const ImuSample& s1,
											 const Vector6d& bias);

/** Discrete noise covariance of one step of length dt: diag(σ_a²/dt, σ_g²/dt, σ_ba²dt, σ_bg²dt) (12×12). */
Eigen::Matrix<double, 12, 12> imu_step_noise(const ImuNoise& noise, double dt);

/** Pre-integrated IMU measurement between two keyframes i and j (samples from t_i to t_j):
 * ΔR, Δv, Δp at the linearisation bias b̄, the bias Jacobians J_Rg, J_va, J_vg, J_pa, J_pg, and the
 * 15×15 covariance of [Δp, Δφ, Δv, b_a,j − b_a,i, b_g,j − b_g,i] (bias random walk included, with its
 * effect on the deltas). The readings are kept so that the measurement can be re-integrated at a new
 * linearisation bias. */
class ImuPreintegration
{
   public:
	ImuPreintegration(const ImuNoise& noise, const Vector6d& linearization_bias);

	/** Appends a reading; from the second on, integrates from the previous one (midpoint). Readings
	 * must come in non-decreasing time (throws std::invalid_argument otherwise). */
	void add_sample(const ImuSample& s);
	/** Integrates the stored readings again at a new linearisation bias. */
	void reintegrate(const Vector6d& linearization_bias);

	const ImuNoise& noise() const { return noise_; }
	const Vector6d& linearization_bias() const { return bias_lin_; }
	const std::vector<ImuSample>& samples() const { return samples_; }
	/** t_j − t_i (0 before two readings). */
	double delta_t() const { return dt_sum_; }
	const Eigen::Matrix3d& delta_R() const { return dR_; }
	const Eigen::Vector3d& delta_v() const { return dv_; }
	const Eigen::Vector3d& delta_p() const { return dp_; }
	/** ∂Δ/∂b: rows [Δp, Δφ, Δv] (9), columns [b_a, b_g] (6). J_Rg = block(3, 3), J_va = block(6, 0),
	 * J_vg = block(6, 3), J_pa = block(0, 0), J_pg = block(0, 3) (the Δφ–b_a block is zero). */
	const Eigen::Matrix<double, 9, 6>& bias_jacobian() const { return J_bias_; }
	const Matrix15d& covariance() const { return cov_; }

	/** First-order bias correction at bias b (δb = b − b̄): ΔR·Exp(J_Rg δb_g), Δv + J_va δb_a + J_vg δb_g,
	 * Δp + J_pa δb_a + J_pg δb_g. */
	Eigen::Matrix3d corrected_delta_R(const Vector6d& bias) const;
	Eigen::Vector3d corrected_delta_v(const Vector6d& bias) const;
	Eigen::Vector3d corrected_delta_p(const Vector6d& bias) const;

	/** Predicted navigation state at t_j from the state at t_i with bias b_i (first-order corrected). */
	NavState predict(const NavState& xi, const Vector6d& bias_i) const;

	/** True when b moved from b̄ by more than the thresholds (per component, accelerometer m/s² and
	 * gyroscope rad/s), where the first-order correction stops being accurate. */
	bool bias_far(const Vector6d& bias, double accel_threshold, double gyro_threshold) const;

   private:
	void reset_integration();
	void integrate_step(const ImuSample& s0, const ImuSample& s1);

	ImuNoise noise_;
	Vector6d bias_lin_;
	std::vector<ImuSample> samples_;
	double dt_sum_ = 0;
	Eigen::Matrix3d dR_;
	Eigen::Vector3d dv_, dp_;
	Eigen::Matrix<double, 9, 6> J_bias_;
	Matrix15d cov_;
};
}  // namespace swba
