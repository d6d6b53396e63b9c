/** \file solver.h
 * Levenberg-Marquardt over a Problem: block-sparse normal equations, Schur complement of the
 * eliminable group, reduced system by dense LLT or CHOLMOD (supernodal), Nielsen's damping update.
 * Options and Summary follow Ceres's conventions (cost = ½Σρ(‖W r‖²)).
 *
 * Factors that cannot be evaluated. A factor whose evaluate() returns false (or a non-finite
 * residual) at the current values is dropped from that linearisation and counted; the cost is the
 * sum over the evaluable factors. The evaluable set can therefore change along a step: a factor may
 * leave its domain (a photometric patch that leaves its image, a point that passes behind one camera)
 * or enter it. Comparing the two totals would credit a step with the whole cost of every factor it
 * pushes out of its domain (and charge it for every factor it brings in), so a step is judged like for
 * like instead (no credit for leaving, no charge for entering):
 *  - the gain ratio is ρ = actual / predicted decrease, both summed over the factors evaluable at
 *    both points: the actual decrease leaves out the factors that left or entered, the model's
 *    predicted decrease leaves out the share of the factors that left (those that entered have no
 *    linear model at x). A step is accepted when ρ > 1e-3, whatever the domain changes; with none,
 *    this is the usual ratio of the two totals, bit for bit;
 *  - an accepted step that changed the evaluable set keeps the trust region radius: the model was
 *    verified on part of the factors only, so Nielsen's enlargement is not earned, and near domain
 *    boundaries the steps do not grow. Steps with no domain change update it as usual;
 *  - nothing is dropped silently: every row of the iteration log says why a step was rejected
 *    (IterationSummary::outcome) and how many factors left or entered their domain and how many
 *    variables lost their last evaluable factor (factors_left, factors_entered, variables_stranded);
 *    Summary::num_unconstrained_variables counts the variables without an evaluable factor at the
 *    solution. Such a variable stays where the step left it: with no evaluable factor its gradient
 *    and its coupling are zero, so it does not move until one of its factors becomes evaluable
 *    again through the factor's other variables (a camera that turns back towards the point).
 * Ceres instead rejects every step at which a residual block cannot be evaluated. Here that rule
 * rejected good steps (ρ ≈ 1.2) whenever one of thousands of photometric patches crossed an image
 * border, and kept rejecting while a weakly constrained point's step (large under Marquardt scaling for
 * any radius) took all its patches out; doc/directba.md has the measurements. */
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
	DenseSchur,    ///< Schur complement, reduced system by dense LLT
	SparseSchur,   ///< Schur complement, reduced system by CHOLMOD
	DenseNormal,   ///< no elimination, full normal equations by dense LLT
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
	/** Stop when |Δcost| / cost ≤ function_tolerance after an accepted step, or after a rejected one whose
	 * predicted decrease is also within it (at the minimum, where only rounding or a stale Jacobian moves
	 * the cost). Default 1e-6. */
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
	/** With Auto: reduced systems of at most this dimension may use dense LLT: always up to 200
	 * unknowns, above that only when ≥ 25 % of the upper block triangle is non-zero. Default 1500. */
	int dense_max_dim = 1500;
	/** Threads for residual/Jacobian evaluation and Hessian/Schur assembly. Default 1. */
	int num_threads = 1;
	/** Print one line per iteration to stdout (Ceres's layout). Default false. */
	bool progress_to_stdout = false;
	/** Stop as soon as the cost is ≤ this value (for time-to-cost benchmarks). Default: off (-1). */
	double stop_at_cost = -1.0;

	/** Throws std::invalid_argument naming the option that is out of range. */
	void validate() const;
	/** The INI keys of these options in `section`: max_iterations, the three tolerances,
	 * linear_solver, dense_max_dim and threads. */
	static IniKeys<SolverOptions> ini_keys(const std::string& section);
};

enum class TerminationType
{
	NotRun,
	Convergence,     ///< function, gradient or parameter tolerance reached
	NoConvergence,   ///< max_iterations reached
	/** numerical failure (non-finite cost, factorization failed repeatedly), or no factor evaluable at the
	 * initial values (every one dropped: nothing to fit) */
	Failure,
	UserCost         ///< stop_at_cost reached
};
/** Ceres's names: "CONVERGENCE", "NO_CONVERGENCE", "FAILURE", "USER_COST", "NOT_RUN". */
const char* to_string(TerminationType t);

/** What became of an LM step. */
enum class StepOutcome
{
	Accepted,
	LinearSolveFailed,    ///< the damped system could not be factorised
	CostNotFinite,        ///< the cost at the trial point is not finite
	NoPredictedDecrease,  ///< the linear model predicts no decrease over the comparable factors
	CostRose,             ///< the cost of the comparable factors did not decrease
	SmallGainRatio        ///< it decreased by less than 1e-3 of the predicted decrease
};

/** Every step outcome with its name, as the iteration log prints it. */
constexpr std::array<EnumName<StepOutcome>, 6> enum_names(StepOutcome)
{
	return {{{StepOutcome::Accepted, "accepted"},
			 {StepOutcome::LinearSolveFailed, "linear solve failed"},
			 {StepOutcome::CostNotFinite, "cost not finite"},
			 {StepOutcome::NoPredictedDecrease, "no predicted decrease"},
			 {StepOutcome::CostRose, "cost rose"},
			 {StepOutcome::SmallGainRatio, "gain ratio below 1e-3"}}};
}

struct IterationSummary
{
	int iteration = 0;
	double cost = 0;               ///< cost after the iteration (over the factors evaluable there)
	double cost_change = 0;        ///< actual decrease over the factors evaluable before and after the step
	double gradient_max_norm = 0;
	double step_norm = 0;
	double model_cost_change = 0;  ///< decrease the linear model predicts, over the same factors
	double relative_decrease = 0;  ///< ρ, gain ratio (actual / predicted decrease, like for like)
	double trust_region_radius = 0;
	bool step_accepted = false;
	StepOutcome outcome = StepOutcome::Accepted;
	int factors_left = 0;          ///< factors evaluable before the step and not at the trial point
	int factors_entered = 0;       ///< factors evaluable at the trial point and not before
	int variables_stranded = 0;    ///< variables with no evaluable factor left at the trial point
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
	int num_unconstrained_variables = 0;  ///< non-constant variables with no evaluable factor at the final values
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
