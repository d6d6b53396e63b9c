/** \file fixed_lag_smoother.h
 * Sensor-free fixed-lag smoothing over a factor graph (GTSAM's FixedLagSmoother / BatchFixedLagSmoother
 * are the model of the split): a Problem (factors + values), the time-ordered states, a marginal prior
 * standing for everything marginalised, first-estimate Jacobians that keep the prior and the factors
 * linearised at one point per state, and a linear tail of states no longer re-linearised. What a state
 * is, which variables leave with the oldest state and how measurements become factors is the caller's
 * business, told through a SmootherClient (e.g. swba/estimators/sliding_window.h,
 * inertial_window.h, or tests/smoother/test_constant_velocity_chain.cpp for a minimal one).
 *
 * One step: add the new state's variables (problem()), add_state(), add_factor() for its factors, then
 * update(client): one LM solve, the client's hooks, and, when the re-linearised states exceed
 * options().relinearized, the oldest one marginalised (with the variables the client says leave with
 * it) into the prior and its conditional kept in the linear tail; a state leaves the smoother for good
 * once more than options().window states are held, and the client receives its final estimate.
 * window = 0: nothing is marginalised (the full history, or a batch: add everything and solve
 * problem() once).
 *
 * \code
 *   swba::smoother::FixedLagSmoother sm(options);           // options.window = W
 *   VariableId x = sm.problem().add_pose(guess);
 *   sm.add_state(t, x);
 *   sm.add_factor(odometry, {previous, x});
 *   sm.update(client);
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
#include <optional>
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

/** How a variable is handled while the marginal prior is the only factor touching it (e.g. a map point
 * no state of the window observes any more). Each is exact (the same Gaussian); they differ in cost. */
enum class PriorOnly
{
	Keep,       ///< solved with the window like any variable
	Eliminate,  ///< eliminated from the prior for each solve and set to its conditional mean afterwards
	/** kept out of the prior as its conditional given the prior's other variables, updated at each
	 * marginalisation (a step costs O(their dimension²) instead of its cube, see prior_only_store.h);
	 * constant in the problem, at its conditional mean after each update(), until it gains a factor or
	 * covariances() asks for it */
	Store,
};

struct FixedLagSmootherOptions
{
	/** States held in total (≥ 2): a state leaves the smoother, its estimate final, when more are held.
	 * 0 = unbounded (nothing is marginalised). Default 0. */
	int window = 0;
	/** Of these, the newest states re-linearised at every update() (2 ≤ relinearized ≤ window); the
	 * older window − relinearized form the linear tail: each kept, frozen at its linearisation, as the
	 * Gaussian conditional of the variables that left with it given the ones they were connected to,
	 * smoothed by back-substitution after every update() (linear_states(); doc/window.md,
	 * "Re-linearised poses"). 0 = window (no tail). Default 0. */
	int relinearized = 0;
	/** Evaluate every factor touching a variable in the prior at that variable's first estimate
	 * (factors are wrapped in FirstEstimateFactor). Default true. */
	bool first_estimate_jacobians = true;
	/** Relative pivot threshold of the eliminations (see swba::eliminate). Default 1e-12. */
	double marginalization_threshold = 1e-12;
	/** LM options of update(). */
	SolverOptions solver;
};

/** A state: a variable and its time. */
struct TimedState
{
	double time = 0;
	VariableId var = -1;
};

/** A state of the linear tail, with its current estimate. */
struct LinearState
{
	double time = 0;
	VariableId var = -1;
	std::vector<double> value;  ///< ambient value of `var` after the last back-substitution
};

/** What a marginalisation did. */
struct MarginalizationSummary
{
	std::set<FactorId> removed;  ///< the factors replaced by the new prior
	/** Of these, factors that could not be evaluated at the current values (their residual is undefined
	 * there, e.g. a point behind the camera): left out of the new prior, their information is lost. */
	int unevaluable_factors = 0;
};

/** What update() did. */
struct UpdateSummary
{
	Summary solver;
	int prior_only_eliminated = 0;  ///< variables held out of the solve (PriorOnly::Eliminate or Store)
	/** The covariances update() was asked for, at its solution (ok with no blocks when none were). */
	CovarianceResult covariance;
	/** The last marginalisation of this update, if one was due (several states leave the re-linearised
	 * ones at once when the client stops keeping them). */
	std::optional<MarginalizationSummary> marginalization;
	double marginalization_seconds = 0;  ///< of the marginalisations and the states leaving, hooks included
};

/** The estimator's side of update(): the decisions the smoother cannot take without knowing what the
 * variables are. Called in this order within one update(): prior_only() (per prior variable), hold(),
 * solved(), then, while the re-linearised states exceed options().relinearized: keep_relinearized()
 * (unless the window is over-full), and if the oldest leaves them, leaving(), left() (no tail),
 * marginalized(), and left() for each state leaving the tail. */
class SmootherClient
{
   public:
	virtual ~SmootherClient() = default;
	/** How `v` is handled while only the prior touches it. Default Keep. */
	virtual PriorOnly prior_only(VariableId v) const;
	/** Right after the solve (values at the solution, the prior-only variables at their conditional
	 * mean, the tail smoothed): may move the values, e.g. hold a free gauge; returns true if it did (the
	 * smoother then brings the stored prior-only variables and the tail along). Default false. */
	virtual bool hold(const UpdateSummary& u);
	/** After hold(): the final values of this solve (online output, covariances, re-association). */
	virtual void solved(const UpdateSummary& u);
	/** The oldest re-linearised state is due to be marginalised: returning true keeps it (and the
	 * states after it) re-linearised for this update, e.g. while a factor on it has a robust weight
	 * still in question, which marginalising would freeze; the linear tail's oldest state leaves in its
	 * place if the window is over-full. Only asked while the re-linearised states alone are at most
	 * options().window: the lag bounds it. Default false. */
	virtual bool keep_relinearized(const TimedState& oldest);
	/** The oldest re-linearised state is about to be marginalised: returns the variables that leave
	 * with it. The client may first re-parameterise variables that depend on it (change_prior_variable). */
	virtual std::set<VariableId> leaving(const TimedState& oldest);
	/** After the oldest state's marginalisation. */
	virtual void marginalized(const TimedState& oldest, const MarginalizationSummary& m);
	/** A state leaves the smoother for good (more than `window` states held): its final estimate. */
	virtual void left(const TimedState& state, const std::vector<double>& value);
};

/** The prior's points a change of variables is built around (change_prior_variable()). */
struct PriorPoints
{
	std::vector<double> old_lin;                  ///< the old variable's linearisation point in the prior
	std::vector<std::vector<double>> others_lin;  ///< of each other variable, in the order asked for
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
	/** The factors and values. Add and remove variables directly (a removed variable's first estimate
	 * is forgotten at the next update()); add factors through add_factor(). */
	Problem& problem() { return problem_; }
	const Problem& problem() const { return problem_; }
	/** Adds a factor, wrapped in a FirstEstimateFactor when first-estimate Jacobians are on, with an
	 * optional robust loss (a robustified factor enters the marginal prior with its IRLS weight at the
	 * current values, as the solver's Triggs correction gives it). */
	FactorId add_factor(std::shared_ptr<const Factor> factor, std::vector<VariableId> variables,
						std::shared_ptr<const LossFunction> loss = nullptr);
	/** Appends `var` at `time` as the newest state. */
	void add_state(double time, VariableId var);
	/** The re-linearised states, oldest first. */
	const std::deque<TimedState>& states() const { return states_; }
	/** The states of the linear tail, oldest first, at their estimates after the last update(). */
	std::vector<LinearState> linear_states() const;

	/** The step: one LM solve of the problem with options().solver (the prior-only variables handled
	 * as client.prior_only() says; the covariances of `covariance` recovered from the solve's last
	 * linearisation), then the client's hooks and the marginalisation of what leaves (see SmootherClient).
	 * A group of `covariance` may name any variable of the model the smoother holds: the problem's, the
	 * prior-only ones held out of the solve (PriorOnly::Store, Eliminate) and the linear tail's
	 * (linear_states(), e.g. the state that leaves the smoother at this update()). Its covariance is
	 * then that of the solve's problem times the Gaussian conditionals of the tail and of the held-out
	 * variables, the Gaussian whose mean the smoother reports (the tail's conditionals are linearised at
	 * their separators' first estimates, the problem at its current values: the same to first order),
	 * at the cost of rows solves and O(rows · size) per conditional; a group of free variables of the
	 * problem costs what it did. With PriorOnly::Store that model is not the full joint: a state that
	 * leaves while variables are stored keeps no coupling with them (the store integrates it out), so
	 * its covariance, like its mean, misses what they later learn.
	 * The marginalisation linearises the factors touching the leaving variables (the prior from its
	 * known information) at the first estimates; the marginal over the variables they connect to
	 * replaces them as the new prior, stored around the first estimates of its variables. */
	UpdateSummary update(SmootherClient& client, const CovarianceRequest& covariance = {});

	/** The marginal prior over its variables (without those PriorOnly::Store holds: see in_prior()). */
	const MarginalPrior& prior() const { return prior_; }
	/** v is a variable of the prior: in prior(), or held by the prior-only store. */
	bool in_prior(VariableId v) const;
	/** v's first estimate, or its current value when it has none (FEJ off or not yet frozen). */
	const double* linearization_point(VariableId v) const;
	/** A change of variables in the prior (see VariableChange): if `old_var` is in the prior (else
	 * returns false and does nothing), brings it and `others` into prior() (an absent one with zero
	 * columns, its first estimate frozen), calls make() with their points there, applies the change
	 * to the prior, the linear tail and the prior-only store, and records the new variable's first
	 * estimate (FEJ on). The caller then replaces old_var in the problem. */
	bool change_prior_variable(VariableId old_var, const std::vector<VariableId>& others,
							   const std::function<VariableChange(const PriorPoints&)>& make);
	/** The covariances of `request` at the current values (a fresh linearisation and factorisation, as
	 * swba::marginal_covariance with options().solver), its groups naming variables of the whole model
	 * as in update(). A group naming a variable of the prior-only store first brings every stored
	 * variable back into prior() (the next update() stores again those still only the prior touches). */
	CovarianceResult covariances(const CovarianceRequest& request);

   private:
	FixedLagSmootherOptions opt_;
	Problem problem_;
	std::shared_ptr<FirstEstimateRegistry> first_estimates_ = std::make_shared<FirstEstimateRegistry>();
	std::deque<TimedState> states_;
	MarginalPrior prior_;
	std::unique_ptr<detail::PriorOnlyStore> store_;
	std::unique_ptr<detail::LinearTail> tail_;

	/** The solve with the prior-only variables handled as `client` says. */
	UpdateSummary solve(const SmootherClient& client, const CovarianceRequest& covariance);
	/** The stored variables that gained a factor or are no longer PriorOnly::Store go back; the active
	 * ones the prior alone touches and the client stores join the store. Returns the store's size. */
	int sync_store(const SmootherClient& client);
	/** The oldest state leaves the re-linearised states, then the tail's oldest while over the window. */
	void marginalize(SmootherClient& client, UpdateSummary& out);
	/** The tail's oldest states leave (client.left()) while more than options().window are held. */
	void leave_tail(SmootherClient& client);
	/** Marginalises the oldest state with `also` (see update()). */
	MarginalizationSummary marginalize_oldest(const std::set<VariableId>& also);
	/** The conditional `c` of the non-constant of `marg` given the kept variables joins the tail (with
	 * the values of the constant ones). */
	void push_linear_state(detail::TailConditional c, const std::set<VariableId>& marg);
	/** The store follows the elimination of c's variables (the conditional of the marginalised
	 * variables given the kept ones) in marginalize_oldest(). */
	void eliminate_from_store(const detail::TailConditional& c);
	/** Freezes v's first estimate at its current value (FEJ on, v not constant and not yet frozen). */
	void freeze(VariableId v);
	/** Removes variable v (and its factors) from the problem, and its first estimate. */
	void remove_variable(VariableId v);
	/** Freezes `v` and brings it into the prior (zero columns) if absent; its index in prior(). */
	int include_in_prior(VariableId v);
	/** The tail's size limit: window − relinearized. */
	int tail_length() const;
};
}  // namespace swba::smoother
