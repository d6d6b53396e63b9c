#include <swba/estimators/inertial_window.h>

#include <stdexcept>

namespace swba::estimators
{
SolverOptions InertialWindowOptions::default_solver()
{
	SolverOptions s;
	s.max_iterations = 10;
	// Nearly Gauss-Newton from the start: the bias random-walk rows are stiff (information 1/(σ_b² Δt),
	// up to 1e15), so Marquardt's damping λ·diag(JᵀJ) with λ = 1e-4 all but freezes the biases' common
	// motion, which only the weak pre-integrated deltas determine; LM then needs tens of iterations to grow
	// its trust region. The window starts from the IMU prediction, close to the optimum.
	s.initial_trust_region_radius = 1e12;
	return s;
}

void InertialWindowOptions::validate() const
{
	if (window_size == 1 || window_size < 0) throw std::invalid_argument("window_size must be 0 or >= 2");
	measurements.noise.validate();
	measurements.prior.validate();
	if (!(reintegrate_accel > 0) || !(reintegrate_gyro > 0))
		throw std::invalid_argument("re-integration thresholds must be positive");
}

IniKeys<InertialWindowOptions> InertialWindowOptions::ini_keys(const std::string& section)
{
	using O = InertialWindowOptions;
	using namespace ini;
	return {
		enum_key<O, KeyframeTimes>(section, "keyframes",
								   "keyframes (and every row's reports) at the pose-prior times, or at every pose reading "
								   "(priors and odometry)",
								   "keyframe times", [](auto& o) -> auto& { return o.measurements.keyframes; }),
		enum_key<O, GaugeMode>(section, "gauge",
							   "four-DoF gauge without pose priors: a prior on the first pose, fixed, or free",
							   "gauge", [](auto& o) -> auto& { return o.gauge; }),
		bool_key<O>(section, "first_estimate_jacobians", "FEJ for the factors touching the marginal prior",
					&O::first_estimate_jacobians),
		number_key<O>(section, "reintegrate_accel", "m/s^2",
					  "re-integrate an IMU factor when the accelerometer bias moves this far from its linearisation",
					  &O::reintegrate_accel, parse_positive),
		number_key<O>(section, "reintegrate_gyro", "rad/s",
					  "re-integrate an IMU factor when the gyroscope bias moves this far from its linearisation",
					  &O::reintegrate_gyro, parse_positive),
	};
}
}  // namespace swba::estimators
