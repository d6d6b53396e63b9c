#include <swba/nonlinear/solver.h>

#include <stdexcept>

namespace swba
{
LinearSolverType parse_linear_solver(const std::string& name)
{
	return parse_enum<LinearSolverType>(name, "linear solver");
}

std::string to_string(LinearSolverType t) { return enum_name(t); }

void SolverOptions::validate() const
{
	const auto check = [](bool ok, const char* msg) {
		if (!ok) throw std::invalid_argument(msg);
	};
	check(max_iterations >= 0, "max_iterations must be >= 0");
	check(function_tolerance >= 0, "function_tolerance must be >= 0");
	check(gradient_tolerance >= 0, "gradient_tolerance must be >= 0");
	check(parameter_tolerance >= 0, "parameter_tolerance must be >= 0");
	check(initial_trust_region_radius > 0, "initial_trust_region_radius must be > 0");
	check(max_trust_region_radius >= initial_trust_region_radius,
		  "max_trust_region_radius must be >= initial_trust_region_radius");
	check(min_lm_diagonal > 0 && max_lm_diagonal >= min_lm_diagonal, "need 0 < min_lm_diagonal <= max_lm_diagonal");
	check(num_threads >= 1, "num_threads must be >= 1");
	check(dense_max_dim >= 0, "dense_max_dim must be >= 0");
}

IniKeys<SolverOptions> SolverOptions::ini_keys(const std::string& section)
{
	using O = SolverOptions;
	using namespace ini;
	return {
		int_key<O>(section, "max_iterations", "iterations", "LM iterations per solve", &O::max_iterations, 1),
		number_key<O>(section, "function_tolerance", "relative", "stop when |d cost| / cost < this",
					  &O::function_tolerance, parse_non_negative),
		number_key<O>(section, "gradient_tolerance", "cost units", "stop when max |gradient| <= this",
					  &O::gradient_tolerance, parse_non_negative),
		number_key<O>(section, "parameter_tolerance", "relative", "stop when |step| <= this * (|x| + this)",
					  &O::parameter_tolerance, parse_non_negative),
		enum_key<O, LinearSolverType>(section, "linear_solver", "linear solver of each LM step", "linear solver",
									  [](auto& o) -> auto& { return o.linear_solver; }),
		int_key<O>(section, "dense_max_dim", "unknowns",
				   "with linear_solver = auto: reduced systems up to this size use dense LLT", &O::dense_max_dim, 0),
		int_key<O>(section, "threads", "count", "threads of the evaluation and assembly", &O::num_threads, 1),
	};
}
}  // namespace swba
