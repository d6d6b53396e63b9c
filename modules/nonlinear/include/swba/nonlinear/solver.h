/** \file solver.h
 * Levenberg-Marquardt over a Problem: block-sparse normal equations, Schur complement of the
 * eliminable group, reduced system by dense LDLT or CHOLMOD (supernodal), Nielsen's damping update.
 * Options and Summary follow Ceres's conventions (cost = ½Σρ(‖W r‖²)). */
#pragma once

#include <swba/core/ini.h>
#include <swba/core/names.h>
#include <swba/nonlinear/problem.h>

#include <array>

#include <string>
#include <vector>

namespace swba
{
enum class LinearSolverType
{
	Auto,          ///< Schur of the eliminable variables not linked to each other by a factor, when their tracks
	               ///< are short (≤ ~15 factors each) or the full system is ≤ dense_max_dim; dense below dense_max_dim
	DenseSchur,    ///< Schur complement, reduced system by dense LDLT
	SparseSchur,   ///< Schur complement, reduced system by CHOLMOD
	DenseNormal,   ///< no elimination, full normal equations by dense LDLT
	SparseNormal   ///< no elimination, full normal equations by CHOLMOD
};

/** Every linear solver with its name, in the order the names are listed to the user. */
constexpr std::array<EnumName<LinearSolverType>, 5> enum_names(LinearSolverType)
{
	return {{{LinearSolverType::Auto, "auto"},
			 {LinearSolverType::DenseSchur, "dense-schur"},
			 {LinearSolverType::SparseSchur, "sparse-schur"},
			 {LinearSolverType::DenseNormal, "dense-normal"},
			 {LinearSolverType::SparseNormal, "sparse-normal"}}};
}

/** Parses "auto", "dense-schur", "sparse-schur", "dense-normal", "sparse-normal". */
LinearSolverType parse_linear_solver(const std::string& name);
std::string to_string(LinearSolverType t);

struct SolverOptions
{
	/** Maximum number of LM iterations (accepted or rejected steps). Default 50. */
	int max_iterations = 50;
	/** Stop when |Δcost| / cost < function_tolerance after an accepted step. Default 1e-6. */
	double function_tolerance = 1e-6;
	/** Stop when max_i |g_i| ≤ gradient_tolerance (g = Jᵀr in the tangent space). Default 1e-10. */
	double gradient_tolerance = 1e-10;
	/** Stop when ‖δ‖ ≤ parameter_tolerance · (‖x‖ + parameter_tolerance). Default 1e-8. */
	double parameter_tolerance = 1e-8;
	/** Initial trust region radius μ₀; the LM damping is λ = 1/μ. Default 1e4 (as Ceres). */
	double initial_trust_region_radius = 1e4;
	/** Bounds of the trust region radius; reaching max_trust... keeps, min stops. */
	double max_trust_region_radius = 1e16;
	double min_trust_region_radius = 1e-32;
	/** Damping D = clamp(diag(JᵀJ), min_lm_diagonal, max_lm_diagonal) (Marquardt scaling). */
	double min_lm_diagonal = 1e-6;
	double max_lm_diagonal = 1e32;
	/** Linear solver. Default Auto. */
	LinearSolverType linear_solver = LinearSolverType::Auto;
	/** With Auto: reduced systems of at most this dimension may use dense LDLT: always up to 200
	 * unknowns, above that only when ≥ 25 % of the upper block triangle is non-zero. Default 1500. */
	int dense_max_dim = 1500;
	/** Threads for residual/Jacobian evaluation and Hessian/Schur assembly. Default 1. */
	int num_threads = 1;
	/** Print one line per iteration to stdout (Ceres's layout). Default false. */
	bool progress_to_stdout = false;
	/** Stop as soon as the cost is ≤ this value (for time-to-cost benchmarks). Default: off (-1). */
	double stop_at_cost = -1.0;

	/** Returns false and sets `why` when an option is out of range. */
	bool is_valid(std::string* why) const;
	/** The INI keys of these options in `section`: max_iterations, the three tolerances,
	 * linear_solver, dense_max_dim and threads. */
	static IniKeys<SolverOptions> ini_keys(const std::string& section);
};

enum class TerminationType
{
	NotRun,
	Convergence,     ///< function, gradient or parameter tolerance reached
	NoConvergence,   ///< max_iterations reached
	Failure,         ///< numerical failure (non-finite cost, factorization failed repeatedly)
	UserCost         ///< stop_at_cost reached
};

struct IterationSummary
{
	int iteration = 0;
	double cost = 0;
	double cost_change = 0;
	double gradient_max_norm = 0;
	double step_norm = 0;
	double relative_decrease = 0;  ///< ρ, gain ratio
	double trust_region_radius = 0;
	bool step_accepted = false;
	double iteration_time_s = 0;
	double cumulative_time_s = 0;
};

struct Summary
{
	TerminationType termination = TerminationType::NotRun;
	std::string message = "not run yet";
	int iterations = 0;             ///< LM iterations performed (accepted + rejected)
	int successful_steps = 0;
	int unsuccessful_steps = 0;
	double initial_cost = -1;
	double final_cost = -1;
	int num_kept_variables = 0;     ///< non-constant variables of the Kept group
	int num_eliminated_variables = 0;
	int num_constant_variables = 0;
	int num_factors = 0;
	int num_dropped_factors = 0;    ///< factors not evaluable at the final values
	int reduced_dim = 0;            ///< size of the system the Cholesky factorizes
	LinearSolverType linear_solver_used = LinearSolverType::Auto;
	double time_evaluation_s = 0;   ///< residuals + Jacobians
	double time_linear_solver_s = 0;///< assembly, Schur, factorization, back-substitution
	double time_total_s = 0;
	std::vector<IterationSummary> iterations_log;

	bool is_solution_usable() const
	{
		return termination == TerminationType::Convergence ||
			   termination == TerminationType::NoConvergence || termination == TerminationType::UserCost;
	}
	/** One line: "LM: cost 1.2e3 -> 4.5e1 in 12 iterations (Convergence: ...)". */
	std::string brief_report() const;
	/** Ceres-like multi-line report with `Initial cost:`/`Final cost:` lines and the time split. */
	std::string full_report() const;
};

/** Ceres-like header and row for the per-iteration log. */
std::string iteration_log_header();
std::string format_iteration(const IterationSummary& it);

/** Runs Levenberg-Marquardt on `problem`, updating its values in place.
 * Throws std::invalid_argument when the options are invalid or the problem is malformed (with
 * DenseSchur/SparseSchur: a factor between two eliminable variables; Auto keeps those in the reduced
 * system instead). */
Summary solve(Problem& problem, const SolverOptions& options = {});
}  // namespace swba
