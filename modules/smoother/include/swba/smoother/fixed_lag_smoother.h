/** \file fixed_lag_smoother.h
 * Sensor-free fixed-lag smoothing over a factor graph (GTSAM's FixedLagSmoother / BatchFixedLagSmoother
 * are the model of the split): a Problem (factors + values), the time-ordered states of the window, a
 * marginal prior standing for everything marginalised, and first-estimate Jacobians that keep the
 * prior and the factors linearised at one point per state. What a state or a landmark is, which
 * variables leave with the oldest state and how measurements become factors is the caller's business
 * (e.g. swba/estimators/sliding_window.h for range-bearing SLAM).
 *
 * Three ways to run the same machinery, through this API only:
 *   - fixed lag: after adding each state and its factors, update() (one LM solve), then, while
 *     over_lag(), marginalize_oldest();
 *   - full history (lag 0): update() after every state, nothing marginalised (the causal optimum);
 *   - batch (lag 0): add everything, then one solve() at the end.
 *
 * \code
 *   swba::smoother::FixedLagSmoother sm(options);           // options.lag = W
 *   VariableId x = sm.problem().add_pose(guess);
 *   sm.add_state(t, x);
 *   sm.add_factor(odometry, {previous, x});
 *   sm.update(is_landmark);
 *   if (sm.over_lag()) sm.marginalize_oldest({});
 * \endcode */
#pragma once

#include <swba/factors/first_estimate.h>
#include <swba/nonlinear/covariance.h>
#include <swba/nonlinear/problem.h>
#include <swba/nonlinear/solver.h>
#include <swba/smoother/marginal_prior.h>

#include <deque>
#include <functional>
#include <memory>
#include <set>
#include <vector>

namespace swba::smoother
{
namespace detail
{
class PriorOnlyStore;
class LinearTail;
struct TailConditional;
}

struct FixedLagSmootherOptions
{
	/** States kept in the window (≥ 2) and re-linearised at every update(); 0 = unbounded (nothing is
	 * marginalised). Default 0. */
	int lag = 0;
	/** States kept after they leave the window, frozen at their linearisation: each as the Gaussian
	 * conditional of the variables that left with it given the ones they were connected to, smoothed
	 * by back-substitution after every update() (linear_states()). The smoothing lag is then
	 * lag + linear_lag at the cost of a window of `lag` (doc/window.md, "Re-linearised poses").
	 * 0 = none: a state leaves the smoother when it leaves the window. Default 0. */
	int linear_lag = 0;
	/** Evaluate every factor touching a variable in the prior at that variable's first estimate
	 * (factors are wrapped in FirstEstimateFactor). Default true. */
	bool first_estimate_jacobians = true;
	/** Relative pivot threshold of the marginal prior (see swba::marginalize). Default 1e-12. */
	double marginalization_threshold = 1e-12;
	/** In update(), hold the variables only the prior touches out of the LM solve and set them to their
	 * conditional optimum afterwards (same optimum, a smaller dense system). Default true. */
	bool eliminate_prior_only = true;
	/** With eliminate_prior_only: keep the prior-only variables out of the prior between solves, as
	 * their conditional given the prior's other variables, updated at each marginalisation, instead of
	 * eliminating them from the whole prior at every update() (the same Gaussian; a step costs
	 * O(prior-only dimension²) instead of its cube, see prior_only_store.h). While stored they are
	 * constant variables of the problem with no factor, at their conditional mean after each update():
	 * a covariance of them needs release_prior_only() first. Default false. */
	bool store_prior_only = false;
	/** LM options of update(). */
	SolverOptions solver;
};

/** A state of the window: a variable and its time. */
struct TimedState
{
	double time = 0;
	VariableId var = -1;
};

/** A state that left the window and is smoothed as a linear conditional, with its current estimate. */
struct LinearState
{
	double time = 0;
	VariableId var = -1;
	std::vector<double> value;  ///< ambient value of `var` after the last back-substitution
};

/** What update() did. */
struct UpdateSummary
{
	Summary solver;
	int prior_only_eliminated = 0;  ///< variables held out of the solve (eliminate_prior_only)
	/** The covariances update() was asked for, at its solution (ok with no blocks when none were). */
	CovarianceResult covariance;
};

/** What marginalize_oldest() did. */
struct MarginalizationSummary
{
	std::set<FactorId> removed;  ///< the factors replaced by the new prior
	/** Of these, factors that could not be evaluated at the current values (their residual is undefined
	 * there, e.g. a landmark behind its anchor): left out of the new prior, their information is lost. */
	int unevaluable_factors = 0;
};

class FixedLagSmoother
{
   public:
	/** Does not validate `options` (the caller's options do). */
	explicit FixedLagSmoother(const FixedLagSmootherOptions& options);
	~FixedLagSmoother();
	FixedLagSmoother(FixedLagSmoother&&) noexcept;
	FixedLagSmoother& operator=(FixedLagSmoother&&) noexcept;

	const FixedLagSmootherOptions& options() const { return opt_; }
	/** The factors and values. Add variables directly; add factors through add_factor(). */
	Problem& problem() { return problem_; }
	const Problem& problem() const { return problem_; }

	/** Adds a factor, wrapped in a FirstEstimateFactor when first-estimate Jacobians are on, with an
	 * optional robust loss (a robustified factor enters the marginal prior with its IRLS weight at the
	 * current values, as the solver's Triggs correction gives it). */
	FactorId add_factor(std::shared_ptr<const Factor> factor, std::vector<VariableId> variables,
						std::shared_ptr<const LossFunction> loss = nullptr);
	/** Appends `var` at `time` as the newest state of the window. */
	void add_state(double time, VariableId var);
	/** The window's states, oldest first. */
	const std::deque<TimedState>& states() const { return states_; }
	/** True when lag > 0 and the window holds more states than the lag: marginalize_oldest() is due. */
	bool over_lag() const;
	/** The states that left the window and are still smoothed (linear_lag > 0), oldest first, at their
	 * estimates after the last update() (or smooth_linear_states()). */
	std::vector<LinearState> linear_states() const;
	/** The number of linear_states() (without copying them). */
	std::size_t num_linear_states() const;
	/** The current estimate of a variable that left the problem with a state still in linear_states()
	 * (nullptr if none). */
	const double* linear_value(VariableId v) const;
	/** True when more states than linear_lag are smoothed: pop_oldest_linear() is due. */
	bool linear_over_lag() const;
	/** Removes the oldest smoothed state and returns it with its estimate (throws std::logic_error if
	 * there is none). */
	LinearState pop_oldest_linear();
	/** Back-substitutes the smoothed states at the problem's current values (update() does it after its
	 * solve; call it again after moving the values, e.g. a gauge hold). */
	void smooth_linear_states();

	/** Freezes v's first estimate at its current value (FEJ on, v not constant and not yet frozen). */
	void freeze(VariableId v);
	/** v's first estimate, or its current value when it has none (FEJ off or not yet frozen). */
	const double* linearization_point(VariableId v) const;
	/** Removes variable v (and its factors) from the problem, and its first estimate. */
	void remove_variable(VariableId v);

	/** The marginal prior over its active variables (with store_prior_only, the prior-only variables
	 * are not among them: see in_prior()). */
	const MarginalPrior& prior() const { return prior_; }
	/** v is a variable of the prior: active, or stored prior-only. */
	bool in_prior(VariableId v) const;
	/** v is a stored prior-only variable (constant in the problem, at its conditional mean). */
	bool is_stored_prior_only(VariableId v) const;
	/** Turns store_prior_only on or off (off: the stored variables are released first). */
	void set_store_prior_only(bool on);
	/** Brings the stored prior-only variable v back among the prior's active variables (no-op if it is
	 * not stored), e.g. before a change of variables of it. */
	void activate(VariableId v);
	/** Brings every stored prior-only variable back (before a covariance of them is asked for). */
	void release_prior_only();
	/** Sets the stored prior-only variables to their conditional mean at the current values (after
	 * the caller moved the active variables, e.g. a gauge hold). update() does it after its solve. */
	void update_prior_only_values();
	/** Freezes `v` and brings it into the prior (zero columns) if absent: a change of variables is
	 * about to make the prior depend on it. Returns its index in prior().variables(). */
	int include_in_prior(VariableId v);
	/** Applies `change` to the prior (MarginalPrior::change_variable), records the new variable's first
	 * estimate (FEJ on) and re-installs the prior's factor. */
	void change_prior_variable(const VariableChange& change);

	/** One LM solve of the window with options().solver; with eliminate_prior_only, the variables that
	 * satisfy `eliminable` and have no factor but the prior are eliminated from it exactly. The
	 * covariances of `covariance` are recovered from the solve's last linearisation (the prior-only
	 * variables eliminated: their elimination leaves the exact marginal of the others; they themselves
	 * are constant in that solve and get zero). */
	UpdateSummary update(const std::function<bool(VariableId)>& eliminable, const CovarianceRequest& covariance = {});
	/** One LM solve of the whole problem with `options` (no elimination): the batch run. */
	Summary solve(const SolverOptions& options);

	/** Marginalises the oldest state together with `also` (variables leaving with it): the factors
	 * touching them are linearised (the prior from its known information) at the first estimates,
	 * the marginal over the variables they connect to replaces them as the new prior, and the
	 * variables are removed. The new prior is stored around the first estimates of its variables. With
	 * linear_lag > 0 the conditional of the removed variables given the kept ones joins linear_states(). */
	MarginalizationSummary marginalize_oldest(const std::set<VariableId>& also);

   private:
	FixedLagSmootherOptions opt_;
	Problem problem_;
	std::shared_ptr<FirstEstimateRegistry> first_estimates_ = std::make_shared<FirstEstimateRegistry>();
	std::deque<TimedState> states_;
	MarginalPrior prior_;
	std::unique_ptr<detail::PriorOnlyStore> store_;
	std::unique_ptr<detail::LinearTail> tail_;

	/** store_prior_only: releases the stored variables that gained a factor and stores the active ones
	 * the prior alone touches. */
	int sync_store(const std::function<bool(VariableId)>& eliminable);
	/** linear_lag > 0: the conditional `c` of the non-constant of `marg` given the kept variables joins
	 * the tail (with the values of the constant ones). */
	void push_linear_state(detail::TailConditional c, const std::set<VariableId>& marg);
	/** store_prior_only: the store follows the elimination of c's variables (the conditional of the
	 * marginalised variables given the kept ones) in marginalize_oldest(). */
	void eliminate_from_store(const detail::TailConditional& c);
};
}  // namespace swba::smoother
