#include <swba/nonlinear/solver.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "normal_equations.h"

namespace swba
{
LinearSolverType parse_linear_solver(const std::string& name)
{
	if (name == "auto") return LinearSolverType::Auto;
	if (name == "dense-schur") return LinearSolverType::DenseSchur;
	if (name == "sparse-schur") return LinearSolverType::SparseSchur;
	if (name == "dense-normal") return LinearSolverType::DenseNormal;
	if (name == "sparse-normal") return LinearSolverType::SparseNormal;
	throw std::invalid_argument("unknown linear solver '" + name +
								"' (expected auto, dense-schur, sparse-schur, dense-normal, sparse-normal)");
}

std::string to_string(LinearSolverType t)
{
	switch (t)
	{
		case LinearSolverType::Auto: return "auto";
		case LinearSolverType::DenseSchur: return "dense-schur";
		case LinearSolverType::SparseSchur: return "sparse-schur";
		case LinearSolverType::DenseNormal: return "dense-normal";
		case LinearSolverType::SparseNormal: return "sparse-normal";
	}
	return "?";
}

static const char* to_string(TerminationType t)
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

std::string iteration_log_header()
{
	return "iter      cost      cost_change  |gradient|   |step|    tr_ratio  tr_radius  iter_time  total_time";
}

std::string format_iteration(const IterationSummary& it)
{
	char buf[200];
	std::snprintf(buf, sizeof(buf), "%4d %13.6e %12.2e %11.2e %9.2e %10.2e %10.2e %10.2e %11.2e%s", it.iteration,
				  it.cost, it.cost_change, it.gradient_max_norm, it.step_norm, it.relative_decrease,
				  it.trust_region_radius, it.iteration_time_s, it.cumulative_time_s,
				  it.iteration > 0 && !it.step_accepted ? "  (rejected)" : "");
	return buf;
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
	std::snprintf(buf, sizeof(buf), "%-30s %s (reduced dimension %d)\n", "Linear solver",
				  to_string(linear_solver_used).c_str(), reduced_dim);
	os << buf;
	std::snprintf(buf, sizeof(buf), "\n%-30s %.12e\n%-30s %.12e\n%-30s %.12e\n", "Initial cost:", initial_cost,
				  "Final cost:", final_cost, "Change:", initial_cost - final_cost);
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

namespace
{
using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0)
{
	return std::chrono::duration<double>(Clock::now() - t0).count();
}
}  // namespace

/** Schur elimination pays when eliminated variables have few observations each (BAL: ~4 per point);
 * with long feature tracks (SLAM: hundreds of poses per landmark) the reduced system fills in
 * (Σ n_l² blocks) and the full sparse normal equations are cheaper. Variables in `linked` stay kept. */
static bool short_tracks(const Problem& problem, const std::set<VariableId>& linked)
{
	double terms = 0, blocks = 0;
	for (const auto& [id, v] : problem.variables())
	{
		if (v.constant || v.group != Group::Eliminable || linked.count(id)) continue;
		const double n = static_cast<double>(v.factors.size());
		terms += n * (n + 1) / 2;
		blocks += n;
	}
	return terms <= 8.0 * std::max(1.0, blocks);
}

/** Auto: reduced systems up to this dimension are always factorised densely. */
constexpr int kAutoDenseAlwaysDim = 200;
/** Auto: between that and dense_max_dim, dense only with at least this upper-block fill. */
constexpr double kAutoDenseMinFill = 0.25;

Summary solve(Problem& problem, const SolverOptions& options)
{
	std::string why;
	if (!options.is_valid(&why)) throw std::invalid_argument("SolverOptions: " + why);
	const auto t_start = Clock::now();
	Summary summary;

	// Choose the linear solver.
	bool use_schur = false, sparse = false;
	LinearSolverType used = options.linear_solver;
	std::unique_ptr<detail::NormalEquations> ne;
	switch (options.linear_solver)
	{
		case LinearSolverType::DenseSchur: use_schur = true; break;
		case LinearSolverType::SparseSchur: use_schur = sparse = true; break;
		case LinearSolverType::DenseNormal: break;
		case LinearSolverType::SparseNormal: sparse = true; break;
		case LinearSolverType::Auto: break;
	}
	if (options.linear_solver == LinearSolverType::Auto)
	{
		// Eliminable variables linked to each other by a factor (a marginalisation prior over landmarks)
		// stay in the reduced system; the others are eliminated when that pays: with short tracks, or
		// whenever the full system would be factorised densely anyway (eliminating a variable seen by n
		// kept blocks costs O((n·t)²) flops, never more than carrying its rows through the dense LLT).
		const std::set<VariableId> linked = detail::linked_eliminable_variables(problem);
		int full_dim = 0, reduced_dim = 0;
		bool has_elim = false;
		for (const auto& [id, v] : problem.variables())
		{
			if (v.constant) continue;
			const int t = v.manifold->tangent_size();
			full_dim += t;
			if (v.group == Group::Eliminable && linked.count(id) == 0)
				has_elim = true;
			else
				reduced_dim += t;
		}
		use_schur = has_elim && (full_dim <= options.dense_max_dim || short_tracks(problem, linked));
		const int dim = use_schur ? reduced_dim : full_dim;
		ne = std::make_unique<detail::NormalEquations>(problem, use_schur, dim > options.dense_max_dim,
													   options.num_threads, linked);
		// Dense only pays when the reduced system is small or mostly filled: a pose graph of 744
		// unknowns with ~5 % block fill factorises ~8× faster with CHOLMOD than with a dense LLT.
		sparse = !(dim <= kAutoDenseAlwaysDim ||
				   (dim <= options.dense_max_dim && ne->reduced_block_fill() >= kAutoDenseMinFill));
		ne->set_sparse(sparse);
		used = use_schur ? (sparse ? LinearSolverType::SparseSchur : LinearSolverType::DenseSchur)
						 : (sparse ? LinearSolverType::SparseNormal : LinearSolverType::DenseNormal);
	}
	else
		ne = std::make_unique<detail::NormalEquations>(problem, use_schur, sparse, options.num_threads);

	summary.linear_solver_used = used;
	summary.num_kept_variables = ne->num_kept();
	summary.num_eliminated_variables = ne->num_elim();
	summary.num_constant_variables = ne->num_constant();
	summary.num_factors = ne->num_factors();
	summary.reduced_dim = ne->kept_dim();
	summary.time_linear_solver_s += seconds_since(t_start);

	auto t0 = Clock::now();
	int dropped = 0;
	double cost = ne->evaluate(true, &dropped);
	summary.time_evaluation_s += seconds_since(t0);
	summary.initial_cost = cost;
	summary.final_cost = cost;
	if (!std::isfinite(cost))
	{
		summary.termination = TerminationType::Failure;
		summary.message = "initial cost is not finite";
		summary.time_total_s = seconds_since(t_start);
		return summary;
	}
	t0 = Clock::now();
	ne->assemble();
	summary.time_linear_solver_s += seconds_since(t0);

	double radius = options.initial_trust_region_radius;
	double decrease_factor = 2.0;
	IterationSummary it0;
	it0.cost = cost;
	it0.gradient_max_norm = ne->gradient_max_norm();
	it0.trust_region_radius = radius;
	it0.step_accepted = true;
	it0.cumulative_time_s = seconds_since(t_start);
	summary.iterations_log.push_back(it0);
	if (options.progress_to_stdout)
	{
		std::cout << iteration_log_header() << "\n" << format_iteration(it0) << "\n";
		std::cout.flush();
	}

	auto finish = [&](TerminationType t, std::string msg) {
		summary.termination = t;
		summary.message = std::move(msg);
	};

	if (ne->kept_dim() + ne->elim_dim() == 0)
		finish(TerminationType::Convergence, "no free variables");
	else if (it0.gradient_max_norm <= options.gradient_tolerance)
		finish(TerminationType::Convergence, "gradient tolerance reached");
	else if (options.stop_at_cost >= 0 && cost <= options.stop_at_cost)
		finish(TerminationType::UserCost, "cost reached stop_at_cost");

	Eigen::VectorXd delta;
	int consecutive_failures = 0;
	while (summary.termination == TerminationType::NotRun)
	{
		if (summary.iterations >= options.max_iterations)
		{
			finish(TerminationType::NoConvergence, "maximum number of iterations reached");
			break;
		}
		const auto t_iter = Clock::now();
		summary.iterations++;
		IterationSummary it;
		it.iteration = summary.iterations;
		t0 = Clock::now();
		const bool solved = ne->solve_damped(1.0 / radius, options.min_lm_diagonal, options.max_lm_diagonal, delta);
		summary.time_linear_solver_s += seconds_since(t0);
		bool accepted = false;
		if (solved)
		{
			it.step_norm = delta.norm();
			const double x_norm = ne->values_norm();
			if (it.step_norm <= options.parameter_tolerance * (x_norm + options.parameter_tolerance))
			{
				finish(TerminationType::Convergence, "parameter tolerance reached");
				summary.iterations--;
				break;
			}
			const double predicted = ne->model_decrease(delta);
			ne->save_values();
			ne->apply_step(delta);
			t0 = Clock::now();
			int dropped_new = 0, newly_dropped = 0;
			const double new_cost = ne->evaluate(false, &dropped_new, &newly_dropped);
			summary.time_evaluation_s += seconds_since(t0);
			it.cost_change = cost - new_cost;
			it.relative_decrease = predicted > 0 ? it.cost_change / predicted : 0.0;
			// A step that makes an evaluable factor unevaluable (e.g. a landmark behind its anchor) is
			// rejected, as Ceres rejects steps whose cost cannot be evaluated.
			if (std::isfinite(new_cost) && newly_dropped == 0 && predicted > 0 && it.relative_decrease > 1e-3)
			{
				accepted = true;
				const double old_cost = cost;
				cost = new_cost;
				const double r = 2.0 * it.relative_decrease - 1.0;
				radius = std::min(options.max_trust_region_radius, radius / std::max(1.0 / 3.0, 1.0 - r * r * r));
				decrease_factor = 2.0;
				t0 = Clock::now();
				ne->evaluate(true, &dropped);
				summary.time_evaluation_s += seconds_since(t0);
				t0 = Clock::now();
				ne->assemble();
				summary.time_linear_solver_s += seconds_since(t0);
				summary.successful_steps++;
				consecutive_failures = 0;
				if (std::abs(old_cost - new_cost) <= options.function_tolerance * old_cost)
					finish(TerminationType::Convergence, "function tolerance reached");
				else if (ne->gradient_max_norm() <= options.gradient_tolerance)
					finish(TerminationType::Convergence, "gradient tolerance reached");
				else if (options.stop_at_cost >= 0 && cost <= options.stop_at_cost)
					finish(TerminationType::UserCost, "cost reached stop_at_cost");
			}
			else
			{
				ne->restore_values();
				if (newly_dropped > 0) ne->evaluate(false, &dropped);  // restore the validity flags
			}
		}
		if (!accepted)
		{
			summary.unsuccessful_steps++;
			radius /= decrease_factor;
			decrease_factor *= 2.0;
			if (!solved) consecutive_failures++;
			if (radius < options.min_trust_region_radius)
				finish(TerminationType::Convergence, "trust region radius below minimum");
			else if (consecutive_failures >= 20)
				finish(TerminationType::Failure, "linear system not positive definite after 20 attempts");
		}
		it.cost = cost;
		it.gradient_max_norm = ne->gradient_max_norm();
		it.trust_region_radius = radius;
		it.step_accepted = accepted;
		it.iteration_time_s = seconds_since(t_iter);
		it.cumulative_time_s = seconds_since(t_start);
		summary.iterations_log.push_back(it);
		if (options.progress_to_stdout)
		{
			std::cout << format_iteration(it) << "\n";
			std::cout.flush();
		}
	}
	summary.final_cost = cost;
	summary.num_dropped_factors = dropped;
	summary.time_total_s = seconds_since(t_start);
	return summary;
}
}  // namespace swba
