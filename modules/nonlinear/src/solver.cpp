// The Levenberg-Marquardt loop (Ceres's TrustRegionMinimizer with its LevenbergMarquardtStrategy):
// evaluation, normal equations and the damped solve are the SolverContext's parts.
#include <swba/core/timing.h>
#include <swba/core/validation.h>
#include <swba/nonlinear/solver.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <stdexcept>

#include "covariance_recovery.h"
#include "solver_context.h"

namespace swba
{
namespace
{
/** A step is accepted when its gain ratio (actual / predicted decrease) exceeds this. */
constexpr double kMinRelativeDecrease = 1e-3;
/** Consecutive failed factorisations after which the solve gives up. */
constexpr int kMaxConsecutiveFailures = 20;

/** The trust region of Levenberg-Marquardt, damping λ = 1/μ, with Nielsen's update: after an
 * accepted step of gain ratio ρ, μ ← min(μ_max, μ / max(1/3, 1 − (2ρ − 1)³)) and ν ← 2; after a
 * rejected one, μ ← μ/ν and ν ← 2ν. */
class LevenbergMarquardtStrategy
{
   public:
	explicit LevenbergMarquardtStrategy(const SolverOptions& options)
		: radius_(options.initial_trust_region_radius), max_radius_(options.max_trust_region_radius)
	{
	}
	double radius() const { return radius_; }
	double lambda() const { return 1.0 / radius_; }
	void step_accepted(double relative_decrease)
	{
		const double r = 2.0 * relative_decrease - 1.0;
		radius_ = std::min(max_radius_, radius_ / std::max(1.0 / 3.0, 1.0 - r * r * r));
		decrease_factor_ = 2.0;
	}
	void step_rejected()
	{
		radius_ /= decrease_factor_;
		decrease_factor_ *= 2.0;
	}

   private:
	double radius_, max_radius_;
	double decrease_factor_ = 2.0;
};

/** One run of the loop over a SolverContext, recorded in a Summary. */
class LevenbergMarquardt
{
   public:
	LevenbergMarquardt(detail::SolverContext& context, const SolverOptions& options, Summary& summary,
					   SteadyClock::time_point t_start)
		: ctx_(context), options_(options), summary_(summary), t_start_(t_start), strategy_(options)
	{
	}
	void run();

   private:
	bool start();
	bool iterate();
	bool try_step(IterationSummary& it);
	StepOutcome judge_step(const detail::TrialEvaluation& trial, IterationSummary& it) const;
	void accept_step(double new_cost, IterationSummary& it);
	void reject_step(bool solved, const IterationSummary& it);
	void check_gradient_and_cost();
	void record(IterationSummary& it, bool accepted);
	double evaluate_with_jacobians();
	void assemble();
	void finish(TerminationType t, const char* message)
	{
		summary_.termination = t;
		summary_.message = message;
	}

	detail::SolverContext& ctx_;
	const SolverOptions& options_;
	Summary& summary_;
	SteadyClock::time_point t_start_;
	LevenbergMarquardtStrategy strategy_;
	double cost_ = 0;
	int dropped_ = 0;
	int consecutive_failures_ = 0;
	Eigen::VectorXd delta_;
};

void LevenbergMarquardt::run()
{
	if (!start())
	{
		summary_.num_dropped_factors = dropped_;
		summary_.num_unconstrained_variables = ctx_.evaluator().count_unconstrained();
		summary_.time_total_s = seconds_since(t_start_);
		return;
	}
	while (summary_.termination == TerminationType::NotRun)
	{
		if (summary_.iterations >= options_.max_iterations)
		{
			finish(TerminationType::NoConvergence, "maximum number of iterations reached");
			break;
		}
		if (!iterate()) break;
	}
	summary_.final_cost = cost_;
	summary_.num_dropped_factors = dropped_;
	summary_.num_unconstrained_variables = ctx_.evaluator().count_unconstrained();
	summary_.time_total_s = seconds_since(t_start_);
}

/** Residuals and Jacobians at the current values (updates dropped_); returns the cost. */
double LevenbergMarquardt::evaluate_with_jacobians()
{
	const auto t0 = SteadyClock::now();
	const double cost = ctx_.evaluator().linearize(&dropped_);
	summary_.time_evaluation_s += seconds_since(t0);
	return cost;
}

/** H and g from the last Jacobian evaluation. */
void LevenbergMarquardt::assemble()
{
	const auto t0 = SteadyClock::now();
	ctx_.equations().assemble();
	summary_.time_linear_solver_s += seconds_since(t0);
}

/** Iteration 0 at the initial values and the criteria already met there; false (Failure) when the
 * initial cost is not finite, or when no factor is evaluable there (a cost of 0 over no factor is no fit:
 * with every factor out of its domain, no variable has a gradient or a step). */
bool LevenbergMarquardt::start()
{
	cost_ = evaluate_with_jacobians();
	summary_.initial_cost = cost_;
	summary_.final_cost = cost_;
	if (!std::isfinite(cost_))
	{
		finish(TerminationType::Failure, "initial cost is not finite");
		return false;
	}
	if (dropped_ > 0 && dropped_ == ctx_.program().num_factors())
	{
		finish(TerminationType::Failure, "every factor dropped at the initial values: nothing to fit");
		return false;
	}
	assemble();
	if (options_.progress_to_stdout) std::cout << iteration_log_header() << "\n";
	IterationSummary it0;
	record(it0, true);
	if (ctx_.program().kept_dim() + ctx_.program().elim_dim() == 0)
		finish(TerminationType::Convergence, "no free variables");
	else
		check_gradient_and_cost();
	return true;
}

void LevenbergMarquardt::check_gradient_and_cost()
{
	if (ctx_.equations().gradient_max_norm() <= options_.gradient_tolerance)
		finish(TerminationType::Convergence, "gradient tolerance reached");
	else if (options_.stop_at_cost >= 0 && cost_ <= options_.stop_at_cost)
		finish(TerminationType::UserCost, "cost reached stop_at_cost");
}

/** One LM iteration: the damped step, then its trial. False when the step is below the parameter
 * tolerance (the loop ends without counting or recording that iteration). */
bool LevenbergMarquardt::iterate()
{
	const auto t_iter = SteadyClock::now();
	summary_.iterations++;
	IterationSummary it;
	it.iteration = summary_.iterations;
	const auto t0 = SteadyClock::now();
	const bool solved = ctx_.eliminator().solve_damped(strategy_.lambda(), options_.min_lm_diagonal,
													   options_.max_lm_diagonal, delta_);
	summary_.time_linear_solver_s += seconds_since(t0);
	bool accepted = false;
	it.outcome = StepOutcome::LinearSolveFailed;
	if (solved)
	{
		it.step_norm = delta_.norm();
		const double x_norm = ctx_.program().values_norm();
		if (it.step_norm <= options_.parameter_tolerance * (x_norm + options_.parameter_tolerance))
		{
			finish(TerminationType::Convergence, "parameter tolerance reached");
			summary_.iterations--;
			return false;
		}
		accepted = try_step(it);
	}
	if (!accepted) reject_step(solved, it);
	it.iteration_time_s = seconds_since(t_iter);
	record(it, accepted);
	return true;
}

/** Moves to x ⊞ δ and keeps it if judge_step accepts it; otherwise restores x (the linearisation at x
 * is untouched by the trial). */
bool LevenbergMarquardt::try_step(IterationSummary& it)
{
	auto& program = ctx_.program();
	program.save_values();
	program.apply_step(delta_);
	const auto t0 = SteadyClock::now();
	const detail::TrialEvaluation trial = ctx_.evaluator().evaluate_trial();
	summary_.time_evaluation_s += seconds_since(t0);
	it.outcome = judge_step(trial, it);
	if (it.outcome == StepOutcome::Accepted)
	{
		accept_step(trial.cost, it);
		return true;
	}
	program.restore_values();
	return false;
}

/** The step rule of solver.h: the gain ratio over the factors evaluable at both the current and the
 * trial point. Fills the step's figures (domain changes, cost change, gain ratio) in `it`. */
StepOutcome LevenbergMarquardt::judge_step(const detail::TrialEvaluation& trial, IterationSummary& it) const
{
	it.factors_left = static_cast<int>(trial.left.size());
	it.factors_entered = trial.entered;
	it.variables_stranded = trial.stranded;
	double predicted = ctx_.equations().model_decrease(delta_);
	for (int f : trial.left) predicted -= ctx_.equations().factor_model_decrease(f, delta_);
	// With no domain change this is exactly cost_ − trial.cost.
	it.cost_change = (cost_ - trial.left_cost) - (trial.cost - trial.entered_cost);
	it.model_cost_change = predicted;
	it.relative_decrease = predicted > 0 ? it.cost_change / predicted : 0.0;
	if (!std::isfinite(trial.cost)) return StepOutcome::CostNotFinite;
	if (!(predicted > 0)) return StepOutcome::NoPredictedDecrease;
	if (!(it.cost_change > 0)) return StepOutcome::CostRose;
	if (!(it.relative_decrease > kMinRelativeDecrease)) return StepOutcome::SmallGainRatio;
	return StepOutcome::Accepted;
}

/** Moves on to the trial point; the trust region follows Nielsen's update only when the step changed
 * no factor's evaluability (solver.h). */
void LevenbergMarquardt::accept_step(double new_cost, IterationSummary& it)
{
	const double old_cost = cost_;
	cost_ = new_cost;
	if (it.factors_left == 0 && it.factors_entered == 0) strategy_.step_accepted(it.relative_decrease);
	evaluate_with_jacobians();  // the cost stays that of the trial evaluation
	assemble();
	summary_.successful_steps++;
	consecutive_failures_ = 0;
	if (std::abs(it.cost_change) <= options_.function_tolerance * old_cost)
		finish(TerminationType::Convergence, "function tolerance reached");
	else
		check_gradient_and_cost();
}

/** A rejected trial ends the solve when both its cost change and the decrease the model predicted for it
 * are within the function tolerance: the solve is at the minimum the model can see, and a smaller trust
 * region would only repeat the rejection (with first-estimate Jacobians the model's minimum is a little
 * off the cost's). A large predicted decrease (an overshoot that happens to land at an equal cost) goes
 * on with a smaller region. */
void LevenbergMarquardt::reject_step(bool solved, const IterationSummary& it)
{
	summary_.unsuccessful_steps++;
	strategy_.step_rejected();
	if (!solved) consecutive_failures_++;
	const double tolerance = options_.function_tolerance * cost_;
	if (solved && std::isfinite(it.cost_change) && std::abs(it.cost_change) <= tolerance &&
		it.model_cost_change <= tolerance)
		finish(TerminationType::Convergence, "function tolerance reached");
	else if (strategy_.radius() < options_.min_trust_region_radius)
		finish(TerminationType::Convergence, "trust region radius below minimum");
	else if (consecutive_failures_ >= kMaxConsecutiveFailures)
		finish(TerminationType::Failure, "linear system not positive definite after 20 attempts");
}

/** Completes `it` with the state after its step (iteration 0: the initial state), logs and prints it. */
void LevenbergMarquardt::record(IterationSummary& it, bool accepted)
{
	it.cost = cost_;
	it.gradient_max_norm = ctx_.equations().gradient_max_norm();
	it.trust_region_radius = strategy_.radius();
	it.step_accepted = accepted;
	it.cumulative_time_s = seconds_since(t_start_);
	summary_.iterations_log.push_back(it);
	if (options_.progress_to_stdout)
	{
		std::cout << format_iteration(it) << "\n";
		std::cout.flush();
	}
}
}  // namespace

Summary solve(Problem& problem, const SolverOptions& options)
{
	return solve(problem, options, CovarianceRequest{}, nullptr);
}

Summary solve(Problem& problem, const SolverOptions& options, const CovarianceRequest& request,
			  CovarianceResult* covariance)
{
	validate_with_prefix(options, "SolverOptions: ");
	const auto t_start = SteadyClock::now();
	Summary summary;
	detail::SolverContext context(problem, options);
	summary.linear_solver_used = context.linear_solver_used();
	summary.num_kept_variables = context.program().num_kept();
	summary.num_eliminated_variables = context.program().num_elim();
	summary.num_constant_variables = context.program().num_constant();
	summary.num_factors = context.program().num_factors();
	summary.reduced_dim = context.program().kept_dim();
	summary.time_linear_solver_s += seconds_since(t_start);
	LevenbergMarquardt(context, options, summary, t_start).run();
	if (covariance)
	{
		*covariance = CovarianceResult{};
		if (request.empty())
			covariance->ok = true;
		else if (summary.is_solution_usable())
			*covariance = detail::recover_covariance(context, request);
		else
			covariance->message = "no usable solution";
	}
	return summary;
}
}  // namespace swba
