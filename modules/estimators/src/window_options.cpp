// Options of the window: names of the landmark parameterisations and policies, defaults, validation.
#include <swba/estimators/sliding_window.h>

#include <cmath>
#include <cstddef>
#include <stdexcept>

namespace swba::estimators
{
namespace
{
template <typename E>
struct Named
{
	const char* name;
	E value;
};

const Named<LandmarkParameterization> kParameterizations[] = {{"inverse-depth", LandmarkParameterization::InverseDepth},
															  {"xyz", LandmarkParameterization::Xyz}};
const Named<LandmarkPolicy> kPolicies[] = {{"slam", LandmarkPolicy::Slam},
										   {"constant-time", LandmarkPolicy::ConstantTime}};

/** The value named `s` in `table`; throws std::invalid_argument naming `what` and the valid names. */
template <typename E, std::size_t N>
E parse_named(const std::string& s, const Named<E> (&table)[N], const std::string& what)
{
	for (const auto& entry : table)
		if (s == entry.name) return entry.value;
	std::string expected;
	for (std::size_t i = 0; i < N; i++) expected += std::string(i == 0 ? "" : i + 1 == N ? " or " : ", ") + table[i].name;
	throw std::invalid_argument("unknown " + what + " '" + s + "' (expected " + expected + ")");
}

template <typename E, std::size_t N>
std::string name_of(E value, const Named<E> (&table)[N])
{
	for (const auto& entry : table)
		if (entry.value == value) return entry.name;
	return "?";
}
}  // namespace

LandmarkParameterization parse_landmark_parameterization(const std::string& s)
{
	return parse_named(s, kParameterizations, "landmark parameterisation");
}
LandmarkPolicy parse_landmark_policy(const std::string& s) { return parse_named(s, kPolicies, "landmark policy"); }
std::string to_string(LandmarkParameterization p) { return name_of(p, kParameterizations); }
std::string to_string(LandmarkPolicy p) { return name_of(p, kPolicies); }

SolverOptions SlidingWindowOptions::default_solver_options()
{
	SolverOptions s;
	s.max_iterations = 10;
	// From a warm start the window's cost settles within 2–3 iterations; 1e-9 added iterations that each
	// moved the cost by < 1e-7 relative (≈ 7.3 instead of ≈ 4.5 per step on kf-slam_6D_demo, same APE to
	// 5 digits). 1e-6 saves one more iteration but moved the lagged APE of the 5000-step run by up to
	// 0.7 %; 1e-7 keeps both runs' APE within 0.1 % (doc/run.md, "Benchmark").
	s.function_tolerance = 1e-7;
	return s;
}

void SlidingWindowOptions::validate() const
{
	if (window_size != 0 && window_size < 2)
		throw std::invalid_argument("window size must be >= 2 (or 0 for unbounded), got " + std::to_string(window_size));
	if (!(gauge_prior_weight > 0)) throw std::invalid_argument("gauge prior weight must be > 0");
	if (!(marginalization_threshold >= 0) || !(marginalization_threshold < 1))
		throw std::invalid_argument("marginalisation threshold must be in [0, 1)");
	for (double s : {sensor_std_range, sensor_std_yaw, sensor_std_pitch})
		if (!std::isfinite(s)) throw std::invalid_argument("sensor noise must be finite");
	std::string why;
	if (!solver.is_valid(&why)) throw std::invalid_argument("solver options: " + why);
}
}  // namespace swba::estimators
