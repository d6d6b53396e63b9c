#include <swba/nonlinear/solver.h>

#include <stdexcept>

namespace swba
{
LinearSolverType parse_linear_solver(const std::string& name)
{
	return parse_enum<LinearSolverType>(name, "linear solver");
}

std::string to_string(LinearSolverType t) { return enum_name(t); }

bool SolverOptions::is_valid(std::string* why) const
{
	auto fail = [&](const char* msg) {
		if (why) *why = msg;
		return false;
	};
	if (max_iterations < 0) return fail("max_iterations must be >= 0");
	if (!(function_tolerance >= 0)) return fail("function_tolerance must be >= 0");
	if (!(gradient_tolerance >= 0)) return fail("gradient_tolerance must be >= 0");
	if (!(parameter_tolerance >= 0)) return fail("parameter_tolerance must be >= 0");
	if (!(initial_trust_region_radius > 0)) return fail("initial_trust_region_radius must be > 0");
	if (!(max_trust_region_radius >= initial_trust_region_radius))
		return fail("max_trust_region_radius must be >= initial_trust_region_radius");
	if (!(min_lm_diagonal > 0) || !(max_lm_diagonal >= min_lm_diagonal))
		return fail("need 0 < min_lm_diagonal <= max_lm_diagonal");
	if (num_threads < 1) return fail("num_threads must be >= 1");
	if (dense_max_dim < 0) return fail("dense_max_dim must be >= 0");
	return true;
}

IniKeys<SolverOptions> SolverOptions::ini_keys(const std::string& section)
{
	using S = std::string;
	using O = SolverOptions;
	using namespace ini;
	return {
		{section, "max_iterations", "iterations", "LM iterations per solve",
		 [](const S& v, O& o) { o.max_iterations = parse_int_min(v, 1); },
		 [](const O& o) { return std::to_string(o.max_iterations); }},
		number_key<O>(section, "function_tolerance", "relative", "stop when |d cost| / cost < this",
					  &O::function_tolerance, parse_non_negative),
		number_key<O>(section, "gradient_tolerance", "cost units", "stop when max |gradient| <= this",
					  &O::gradient_tolerance, parse_non_negative),
		number_key<O>(section, "parameter_tolerance", "relative", "stop when |step| <= this * (|x| + this)",
					  &O::parameter_tolerance, parse_non_negative),
		enum_key<O, LinearSolverType>(section, "linear_solver", "linear solver of each LM step", "linear solver",
									  [](auto& o) -> auto& { return o.linear_solver; }),
		{section, "dense_max_dim", "unknowns", "with linear_solver = auto: reduced systems up to this size use dense LDLT",
		 [](const S& v, O& o) { o.dense_max_dim = parse_int_min(v, 0); },
		 [](const O& o) { return std::to_string(o.dense_max_dim); }},
		{section, "threads", "count", "threads of the evaluation and assembly",
		 [](const S& v, O& o) { o.num_threads = parse_int_min(v, 1); },
		 [](const O& o) { return std::to_string(o.num_threads); }},
	};
}
}  // namespace swba
