// Options of the window: names of the landmark parameterisations and policies, defaults, validation.
#include <swba/estimators/sliding_window.h>

#include <swba/core/chi2.h>
#include <swba/core/validation.h>

#include <cmath>
#include <stdexcept>

namespace swba::estimators
{
PoseModel resolve_pose_model(PoseModel model, const std::vector<io::RawlogStep>& steps)
{
	if (model != PoseModel::Auto) return model;
	return io::is_planar(steps) ? PoseModel::Planar : PoseModel::Spatial;
}

LandmarkParameterization parse_landmark_parameterization(const std::string& s)
{
	return parse_enum<LandmarkParameterization>(s, "landmark parameterisation");
}
LandmarkPolicy parse_landmark_policy(const std::string& s) { return parse_enum<LandmarkPolicy>(s, "landmark policy"); }
std::string to_string(LandmarkParameterization p) { return enum_name(p); }
std::string to_string(LandmarkPolicy p) { return enum_name(p); }

SolverOptions SlidingWindowOptions::default_solver_options()
{
	SolverOptions s;
	s.max_iterations = 10;
	// From a warm start the window's cost settles within a few iterations: a tighter tolerance adds
	// iterations that no longer move the APE, a looser one moves the lagged APE of long runs
	// (measurements: doc/benchmarks/run.md, "Benchmark: `swba_bench_window`").
	s.function_tolerance = 1e-7;
	return s;
}

void SlidingWindowOptions::validate() const
{
	if (window_size != 0 && window_size < 2)
		throw std::invalid_argument("window size must be >= 2 (or 0 for unbounded), got " + std::to_string(window_size));
	if (relinearized_poses != 0 && relinearized_poses < 2)
		throw std::invalid_argument("re-linearised poses must be >= 2 (or 0 for the whole window), got " +
									std::to_string(relinearized_poses));
	if (!(gauge_prior_weight > 0)) throw std::invalid_argument("gauge prior weight must be > 0");
	if (!(marginalization_threshold >= 0) || !(marginalization_threshold < 1))
		throw std::invalid_argument("marginalisation threshold must be in [0, 1)");
	if (!(gate_probability > 0 && gate_probability < 1))
		throw std::invalid_argument("gate probability must be in (0, 1), got " + std::to_string(gate_probability));
	if (!(robust_probability > 0 && robust_probability < 1))
		throw std::invalid_argument("robust-loss probability must be in (0, 1), got " + std::to_string(robust_probability));
	if (!(association_pose_inflation >= 1))
		throw std::invalid_argument("association pose inflation must be >= 1 (1: off), got " +
									std::to_string(association_pose_inflation));
	if (young_landmark_readings < 0)
		throw std::invalid_argument("young landmark readings must be >= 0, got " + std::to_string(young_landmark_readings));
	if (policy == LandmarkPolicy::Map && gauge == GaugeMode::Free)
		throw std::invalid_argument("the map landmark policy needs the fixed or the prior gauge: its map is in the frame "
									"of the first pose, which a free gauge does not hold");
	sensor.validate();
	validate_with_prefix(solver, "solver options: ");
}

int SlidingWindowOptions::relinearized_window() const
{
	if (window_size == 0 || relinearized_poses == 0 || policy != LandmarkPolicy::Slam || gauge == GaugeMode::Free)
		return window_size;
	return std::min(relinearized_poses, window_size);
}

double SlidingWindowOptions::gate_threshold(int dof) const { return chi2_quantile(gate_probability, dof); }

double SlidingWindowOptions::robust_scale_squared(int dof) const { return chi2_quantile(robust_probability, dof); }

std::shared_ptr<const LossFunction> SlidingWindowOptions::reading_loss(int dof) const
{
	return robust_loss == RobustLoss::None ? nullptr : make_loss(robust_loss, std::sqrt(robust_scale_squared(dof)));
}

namespace
{
double parse_probability(const std::string& v)
{
	const double p = ini::parse_double(v);
	if (!(p > 0 && p < 1)) throw std::invalid_argument("'" + v + "' must be in (0, 1)");
	return p;
}

/** The keys of the state and its solve: parameterisation, model, gauge, marginalisation, re-linearised poses. */
IniKeys<SlidingWindowOptions> state_keys(const std::string& section)
{
	using S = std::string;
	using O = SlidingWindowOptions;
	using namespace ini;
	return {
		enum_key<O, LandmarkParameterization>(section, "landmarks", "landmark parameterisation",
											  "landmark parameterisation", [](auto& o) -> auto& { return o.landmarks; }),
		enum_key<O, PoseModel>(section, "model", "robot model: auto (from the data), 6d or 2d (planar)", "robot model",
							   [](auto& o) -> auto& { return o.model; }),
		enum_key<O, GaugeMode>(section, "gauge", "gauge: first pose fixed, free, or an SE(3) prior on it", "gauge",
							   [](auto& o) -> auto& { return o.gauge; }),
		number_key<O>(section, "gauge_prior_weight", "1/(m^2 or rad^2)",
					  "information of the gauge prior (gauge = prior only)", &O::gauge_prior_weight, parse_positive),
		{section, "marginalization_threshold", "relative", "relative eigenvalue cut of the marginal prior, in [0, 1)",
		 [](const S& v, O& o) {
			 const double d = parse_non_negative(v);
			 if (!(d < 1)) throw std::invalid_argument("'" + v + "' must be < 1");
			 o.marginalization_threshold = d;
		 },
		 [](const O& o) { return format_double(o.marginalization_threshold); }},
		{section, "relinearized_poses", "integer >= 2, or 0",
		 "poses of the window re-linearised at every step (the newest); the older ones are smoothed as "
		 "frozen linear conditionals (doc/window.md); 0 = the whole window",
		 [](const S& v, O& o) {
			 const int k = ini::parse_int_min(v, 0);
			 if (k == 1) throw std::invalid_argument("'" + v + "' must be >= 2 or 0");
			 o.relinearized_poses = k;
		 },
		 [](const O& o) { return std::to_string(o.relinearized_poses); }},
	};
}

/** The keys of the readings: gate, robust loss, covariances, association and the young-readings rule. */
IniKeys<SlidingWindowOptions> reading_keys(const std::string& section)
{
	using O = SlidingWindowOptions;
	using namespace ini;
	return {
		bool_key<O>(section, "gate", "chi-square gate of the bearing-range readings (doc/outliers.md)",
					&O::gate_readings),
		number_key<O>(section, "gate_probability", "probability in (0, 1)",
					  "share of correct readings the gate passes (chi-square, 3 DoF in 6D, 2 in 2D)", &O::gate_probability,
					  parse_probability),
		enum_key<O, RobustLoss>(section, "robust_loss", "robust loss of the range-bearing factors (window and batch)",
								"robust loss", [](auto& o) -> auto& { return o.robust_loss; }),
		number_key<O>(section, "robust_probability", "probability in (0, 1)",
					  "robust-loss scale: sqrt of the chi-square quantile at this probability (3 DoF in 6D, 2 in 2D)",
					  &O::robust_probability, parse_probability),
		bool_key<O>(section, "covariances", "marginal covariances of every reported pose and landmark (.cov files)",
					&O::covariances),
		enum_key<O, DataAssociation>(section, "association",
									 "data association of the readings: auto (the readings' IDs if they have "
									 "them, else jcbb), ids, nn or jcbb (doc/association.md)",
									 "data association", [](auto& o) -> auto& { return o.association; }),
		bool_key<O>(section, "reassociate",
					"data association: move a window reading that no longer fits its landmark to the one it fits "
					"(doc/association.md)",
					&O::reassociate),
		number_key<O>(section, "association_pose_inflation", "number >= 1",
					  "data association: a reading that would start a landmark is tested again with the pose's "
					  "covariance times this (1 = off; doc/association.md)",
					  &O::association_pose_inflation, parse_positive),
		int_key<O>(section, "young_landmark_readings", "integer >= 0",
				   "a pose with a reading of a landmark read fewer times than this stays re-linearised, so the "
				   "reading's robust weight is not frozen yet (doc/window.md); 0 = never",
				   &O::young_landmark_readings, 0),
		bool_key<O>(section, "young_readings_test",
					"keep young landmarks' readings re-linearised only until a sequential test finds the readings "
					"fit their declared noise; false: for the whole run",
					&O::young_readings_test),
	};
}
}  // namespace

IniKeys<SlidingWindowOptions> SlidingWindowOptions::ini_keys(const std::string& section)
{
	IniKeys<SlidingWindowOptions> keys = state_keys(section);
	for (auto& k : reading_keys(section)) keys.push_back(std::move(k));
	return keys;
}
}  // namespace swba::estimators
