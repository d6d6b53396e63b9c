#include <swba/nonlinear/solver.h>

#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>

namespace swba
{
const char* to_string(TerminationType t)
{
	switch (t)
	{
		case TerminationType::NotRun: return "NOT_RUN";
		case TerminationType::Convergence: return "CONVERGENCE";
		case TerminationType::NoConvergence: return "NO_CONVERGENCE";
		case TerminationType::Failure: return "FAILURE";
		case TerminationType::UserCost: return "USER_COST";
	}
	return "?";
}

namespace
{
/** "" or "  (rejected: <why>; <domain changes>)" / "  (<domain changes>)" for an accepted step. */
std::string step_note(const IterationSummary& it)
{
	std::string note;
	if (it.iteration > 0 && !it.step_accepted)
	{
		note = "rejected: ";
		note += enum_name(it.outcome);
	}
	std::string domain;
	if (it.factors_left > 0)
		domain = std::to_string(it.factors_left) + (it.factors_left == 1 ? " factor" : " factors") + " left their domain";
	if (it.factors_entered > 0)
		domain += (domain.empty() ? "" : ", ") + std::to_string(it.factors_entered) + " entered";
	if (it.variables_stranded > 0)
		domain += "; " + std::to_string(it.variables_stranded) +
				  (it.variables_stranded == 1 ? " variable lost its last factor" : " variables lost their last factor");
	if (!domain.empty()) note += (note.empty() ? "" : "; ") + domain;
	return note.empty() ? "" : "  (" + note + ")";
}
}  // namespace

std::string iteration_log_header()
{
	return "iter      cost      cost_change  |gradient|   |step|    tr_ratio  tr_radius  iter_time  total_time";
}

std::string format_iteration(const IterationSummary& it)
{
	char buf[200];
	std::snprintf(buf, sizeof(buf), "%4d %13.6e %12.2e %11.2e %9.2e %10.2e %10.2e %10.2e %11.2e", it.iteration,
				  it.cost, it.cost_change, it.gradient_max_norm, it.step_norm, it.relative_decrease,
				  it.trust_region_radius, it.iteration_time_s, it.cumulative_time_s);
	return buf + step_note(it);
}

std::string Summary::brief_report() const
{
	std::ostringstream os;
	os.precision(6);
	os << "LM: cost " << std::scientific << initial_cost << " -> " << final_cost << " in " << iterations
	   << " iterations (" << to_string(termination) << ": " << message << ")";
	return os.str();
}

std::string Summary::full_report() const
{
	std::ostringstream os;
	char buf[256];
	os << "\nSolver Summary (swba LM)\n\n";
	std::snprintf(buf, sizeof(buf), "%-30s %d kept + %d eliminated (%d constant)\n", "Variables",
				  num_kept_variables, num_eliminated_variables, num_constant_variables);
	os << buf;
	std::snprintf(buf, sizeof(buf), "%-30s %d (%d dropped at the solution)\n", "Factors", num_factors,
				  num_dropped_factors);
	os << buf;
	if (num_unconstrained_variables > 0)
	{
		std::snprintf(buf, sizeof(buf), "%-30s %d (no evaluable factor at the solution)\n", "Unconstrained variables",
					  num_unconstrained_variables);
		os << buf;
	}
	std::snprintf(buf, sizeof(buf), "%-30s %s (reduced dimension %d)\n", "Linear solver",
				  to_string(linear_solver_used).c_str(), reduced_dim);
	os << buf;
	std::snprintf(buf, sizeof(buf), "\n%-30s %.12e\n%-30s %.12e\n", "Initial cost:", initial_cost, "Final cost:",
				  final_cost);
	os << buf;
	// inf - inf would print nan: no change is defined when a cost is not finite.
	if (std::isfinite(initial_cost) && std::isfinite(final_cost))
		std::snprintf(buf, sizeof(buf), "%-30s %.12e\n", "Change:", initial_cost - final_cost);
	else
		std::snprintf(buf, sizeof(buf), "%-30s - (a cost is not finite)\n", "Change:");
	os << buf;
	std::snprintf(buf, sizeof(buf), "\n%-30s %d (%d successful, %d unsuccessful)\n", "Iterations:", iterations,
				  successful_steps, unsuccessful_steps);
	os << buf;
	std::snprintf(buf, sizeof(buf), "\n%-30s %.4f s\n%-30s %.4f s\n%-30s %.4f s\n", "Residual+Jacobian time:",
				  time_evaluation_s, "Linear solver time:", time_linear_solver_s, "Total time:", time_total_s);
	os << buf;
	os << "\nTermination: " << to_string(termination) << " (" << message << ")\n";
	return os.str();
}
}  // namespace swba
