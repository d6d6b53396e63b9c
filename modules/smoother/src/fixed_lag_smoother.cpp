#include <swba/smoother/fixed_lag_smoother.h>

#include "dense_normal_system.h"
#include "linear_tail.h"
#include "model_covariance.h"
#include "prior_only_elimination.h"
#include "prior_only_store.h"

#include <swba/linear/marginal.h>

#include <swba/core/timing.h>
#include <stdexcept>

namespace swba::smoother
{
FixedLagSmoother::FixedLagSmoother(const FixedLagSmootherOptions& options)
	: opt_(options),
	  store_(std::make_unique<detail::PriorOnlyStore>()),
	  tail_(std::make_unique<detail::LinearTail>())
{
}
FixedLagSmoother::~FixedLagSmoother() = default;
FixedLagSmoother::FixedLagSmoother(FixedLagSmoother&&) noexcept = default;
FixedLagSmoother& FixedLagSmoother::operator=(FixedLagSmoother&&) noexcept = default;

PriorOnly SmootherClient::prior_only(VariableId) const { return PriorOnly::Keep; }
bool SmootherClient::hold(const UpdateSummary&) { return false; }
void SmootherClient::solved(const UpdateSummary&) {}
bool SmootherClient::keep_relinearized(const TimedState&) { return false; }
std::set<VariableId> SmootherClient::leaving(const TimedState&) { return {}; }
void SmootherClient::marginalized(const TimedState&, const MarginalizationSummary&) {}
void SmootherClient::left(const TimedState&, const std::vector<double>&) {}

bool FixedLagSmoother::in_prior(VariableId v) const { return prior_.index_of(v) >= 0 || store_->contains(v); }

CovarianceResult FixedLagSmoother::covariances(const CovarianceRequest& request)
{
	bool stored = false;
	for (const auto& g : request.groups)
		for (VariableId v : g) stored = stored || store_->contains(v);
	if (stored) store_->release(problem_, prior_, store_->variables());
	const detail::ModelCovariance model(request, problem_, *tail_, *store_, nullptr);
	return model.answer(marginal_covariance(problem_, model.problem_request(), opt_.solver));
}

int FixedLagSmoother::sync_store(const SmootherClient& client)
{
	std::vector<VariableId> back, leaving;
	for (VariableId v : store_->variables())
		if (!problem_.variable(v).factors.empty() || client.prior_only(v) != PriorOnly::Store) back.push_back(v);
	store_->release(problem_, prior_, back);
	if (prior_.installed())
		for (VariableId v : prior_.variables())
		{
			const auto& var = problem_.variable(v);
			if (!var.constant && var.factors.size() == 1 && *var.factors.begin() == prior_.factor() &&
				client.prior_only(v) == PriorOnly::Store)
				leaving.push_back(v);
		}
	store_->absorb(problem_, prior_, leaving, opt_.marginalization_threshold);
	return static_cast<int>(store_->variables().size());
}

FactorId FixedLagSmoother::add_factor(std::shared_ptr<const Factor> factor, std::vector<VariableId> variables,
									  std::shared_ptr<const LossFunction> loss)
{
	if (opt_.first_estimate_jacobians)
		factor = std::make_shared<FirstEstimateFactor>(std::move(factor), variables, first_estimates_);
	return problem_.add_factor(std::move(factor), std::move(variables), std::move(loss));
}

void FixedLagSmoother::add_state(double time, VariableId var) { states_.push_back({time, var}); }

std::vector<LinearState> FixedLagSmoother::linear_states() const
{
	std::vector<LinearState> out;
	for (const auto& c : tail_->conditionals()) out.push_back({c.time, c.state, *tail_->value(c.state)});
	return out;
}

int FixedLagSmoother::tail_length() const
{
	return opt_.relinearized > 0 && opt_.window > 0 ? opt_.window - opt_.relinearized : 0;
}

void FixedLagSmoother::freeze(VariableId v)
{
	if (!opt_.first_estimate_jacobians) return;
	if (first_estimates_->count(v) || problem_.is_constant(v)) return;
	(*first_estimates_)[v] = problem_.variable(v).value;
}

const double* FixedLagSmoother::linearization_point(VariableId v) const
{
	auto it = first_estimates_->find(v);
	return it != first_estimates_->end() ? it->second.data() : problem_.value(v);
}

void FixedLagSmoother::remove_variable(VariableId v)
{
	first_estimates_->erase(v);
	problem_.remove_variable(v);
}

int FixedLagSmoother::include_in_prior(VariableId v)
{
	freeze(v);
	return prior_.add_variable(problem_, v);
}

bool FixedLagSmoother::change_prior_variable(VariableId old_var, const std::vector<VariableId>& others,
											 const std::function<VariableChange(const PriorPoints&)>& make)
{
	if (!in_prior(old_var)) return false;
	if (store_->contains(old_var)) store_->release(problem_, prior_, {old_var});  // changed among the active
	std::vector<int> index;
	for (VariableId y : others) index.push_back(include_in_prior(y));
	const auto& lin = prior_.linearization_points();
	PriorPoints points;
	const std::vector<double> old_lin = lin[static_cast<std::size_t>(prior_.index_of(old_var))];
	points.old_lin = old_lin;
	for (int i : index) points.others_lin.push_back(lin[static_cast<std::size_t>(i)]);
	const VariableChange change = make(points);
	if (change.old_var != old_var) throw std::invalid_argument("change_prior_variable: the change is of another variable");
	prior_.change_variable(problem_, change);
	store_->change_active(change);
	// The tail takes the prior's linearisation points of the change (its relation holds around them).
	tail_->change_variable(change, *problem_.variable(change.old_var).manifold, old_lin, [&](VariableId y) {
		return prior_.linearization_points()[static_cast<std::size_t>(prior_.index_of(y))];
	});
	if (opt_.first_estimate_jacobians) (*first_estimates_)[change.new_var] = change.first_estimate;
	prior_.install(problem_);
	return true;
}

UpdateSummary FixedLagSmoother::solve(const SmootherClient& client, const CovarianceRequest& covariance)
{
	UpdateSummary out;
	out.prior_only_eliminated = sync_store(client);
	detail::PriorOnlyElimination elimination;
	const auto eliminable = [&](VariableId v) { return client.prior_only(v) == PriorOnly::Eliminate; };
	// The elimination's covariance, when a group names a variable it may hold or a tail's separator may.
	bool held = false;
	for (const auto& g : covariance.groups)
		for (VariableId v : g) held = held || !problem_.has_variable(v) || eliminable(v);
	const bool reduced =
		prior_.installed() && elimination.begin(problem_, prior_, opt_.marginalization_threshold, eliminable, held);
	const detail::ModelCovariance model(covariance, problem_, *tail_, *store_, reduced ? &elimination : nullptr);
	out.solver = swba::solve(problem_, opt_.solver, model.problem_request(), &out.covariance);
	out.covariance = model.answer(std::move(out.covariance));
	if (reduced)
	{
		out.prior_only_eliminated += elimination.num_eliminated();
		elimination.end(problem_, prior_);
	}
	store_->set_values(problem_, prior_);
	tail_->back_substitute(problem_);
	return out;
}

UpdateSummary FixedLagSmoother::update(SmootherClient& client, const CovarianceRequest& covariance)
{
	// Variables the caller removed from the problem: their first estimates go too (ids are not reused).
	for (auto it = first_estimates_->begin(); it != first_estimates_->end();)
		it = problem_.has_variable(it->first) ? std::next(it) : first_estimates_->erase(it);
	UpdateSummary out = solve(client, covariance);
	if (client.hold(out))
	{
		store_->set_values(problem_, prior_);
		tail_->back_substitute(problem_);
	}
	client.solved(out);
	const int relinearized = opt_.relinearized > 0 ? opt_.relinearized : opt_.window;
	while (opt_.window > 0 && static_cast<int>(states_.size()) > relinearized)
	{
		// The oldest re-linearised state may stay while the re-linearised states alone fit in the
		// window: the tail's oldest then leaves in its place.
		if (static_cast<int>(states_.size()) <= opt_.window && client.keep_relinearized(states_.front()))
		{
			const auto t0 = SteadyClock::now();
			leave_tail(client);  // in the kept state's place
			out.marginalization_seconds += seconds_since(t0);
			break;
		}
		marginalize(client, out);
	}
	return out;
}

void FixedLagSmoother::marginalize(SmootherClient& client, UpdateSummary& out)
{
	const auto t0 = SteadyClock::now();
	const TimedState oldest = states_.front();
	const std::set<VariableId> also = client.leaving(oldest);
	if (tail_length() == 0) client.left(oldest, problem_.variable(oldest.var).value);
	MarginalizationSummary m = marginalize_oldest(also);
	client.marginalized(oldest, m);
	leave_tail(client);
	out.marginalization = std::move(m);
	out.marginalization_seconds += seconds_since(t0);
}

void FixedLagSmoother::leave_tail(SmootherClient& client)
{
	// The tail holds at most window − relinearized states, fewer while the client keeps states
	// re-linearised: its oldest leaves while more than `window` states are held in all.
	while (!tail_->empty() && static_cast<int>(tail_->size() + states_.size()) > opt_.window)
	{
		const auto& c = tail_->conditionals().front();
		const TimedState s{c.time, c.state};
		const std::vector<double> value = *tail_->value(c.state);
		tail_->pop_front();
		client.left(s, value);
	}
}

MarginalizationSummary FixedLagSmoother::marginalize_oldest(const std::set<VariableId>& also)
{
	std::set<VariableId> marg = also;
	marg.insert(states_.front().var);
	// The factors touching the marginalised variables, and their other variables (kept).
	std::set<FactorId> factors;
	for (VariableId v : marg)
		for (FactorId f : problem_.variable(v).factors) factors.insert(f);
	std::vector<VariableId> keep, margv;
	std::set<VariableId> seen;
	for (FactorId f : factors)
		for (VariableId v : problem_.factor(f).variables)
			if (!marg.count(v) && !problem_.is_constant(v) && seen.insert(v).second) keep.push_back(v);
	for (VariableId v : marg)
		if (!problem_.is_constant(v)) margv.push_back(v);
	for (VariableId v : keep) freeze(v);
	// Dense linearisation (FEJ through the decorators) and Schur complement; the old prior enters from
	// its known information (no JᵀJ over its whole state per step).
	std::vector<VariableId> order = keep;
	order.insert(order.end(), margv.begin(), margv.end());
	const MarginalPrior* known = prior_.installed() && prior_.has_information() ? &prior_ : nullptr;
	const detail::DenseNormalSystem sys =
		detail::dense_normal_system(problem_, order, std::vector<FactorId>(factors.begin(), factors.end()), known);
	const int num_keep = sys.offsets[keep.size()];
	std::vector<std::vector<double>> x_lin;
	for (VariableId v : keep)
	{
		const double* x = linearization_point(v);
		x_lin.emplace_back(x, x + problem_.variable(v).manifold->ambient_size());
	}
	// One elimination: the marginal is the new prior; the store and the tail both need the conditional of
	// the marginalised variables given the kept.
	const bool conditional = !store_->empty() || tail_length() > 0;
	GaussianElimination e =
		eliminate(partition_leading(sys.H, sys.b, num_keep), opt_.marginalization_threshold, conditional);
	if (conditional)
	{
		detail::TailConditional c = detail::make_tail_conditional(problem_, keep, x_lin, margv, std::move(e.conditional));
		if (!store_->empty()) eliminate_from_store(c);
		if (tail_length() > 0) push_linear_state(std::move(c), marg);
	}
	MarginalizationResult m = std::move(e.marginal);
	// Those factors and variables are replaced by the new prior.
	if (prior_.installed() && factors.count(prior_.factor())) prior_.forget_factor();  // removed below
	for (FactorId f : factors) problem_.remove_factor(f);
	for (VariableId v : marg) remove_variable(v);
	states_.pop_front();
	// The new prior is stored around the first estimates of its variables (their current values without FEJ).
	prior_.reset(problem_, std::move(keep), std::move(m), std::move(x_lin));
	return {std::move(factors), sys.unevaluable};
}

void FixedLagSmoother::push_linear_state(detail::TailConditional c, const std::set<VariableId>& marg)
{
	c.time = states_.front().time;
	c.state = states_.front().var;
	for (VariableId v : marg)
		if (problem_.is_constant(v))
		{
			c.constants[v] = problem_.variable(v).value;
			c.constant_dims[v] = problem_.variable(v).manifold->tangent_size();
		}
	tail_->push(std::move(c));
}

void FixedLagSmoother::eliminate_from_store(const detail::TailConditional& c)
{
	// c is d_M = k − K d_S in the coordinates of its own linearisation (the current values of M, the new
	// prior's x_lin for S); the store keeps M in the old prior's (or M's first estimates): d_M shifts by
	// s_M = x_current ⊟ x_lin_store. A kept variable whose linearisation point moves (no FEJ) shifts the
	// store's coordinates of S.
	for (std::size_t i = 0; i < c.sep.size(); i++)
	{
		const int idx = prior_.index_of(c.sep[i]);
		if (idx < 0) continue;
		Eigen::VectorXd t(c.sep_dims[i]);
		problem_.variable(c.sep[i]).manifold->minus(
			c.sep_lin[i].data(), prior_.linearization_points()[static_cast<std::size_t>(idx)].data(), t.data());
		store_->shift_active(c.sep[i], t);
	}
	Eigen::VectorXd k_m = c.k;
	std::vector<int> marg_dims;
	for (std::size_t i = 0, off = 0; i < c.vars.size(); i++)
	{
		const int idx = prior_.index_of(c.vars[i]);
		const double* lin = idx >= 0 ? prior_.linearization_points()[static_cast<std::size_t>(idx)].data()
									 : linearization_point(c.vars[i]);
		const int n = c.manifolds[i]->tangent_size();
		Eigen::VectorXd s(n);
		c.manifolds[i]->minus(c.x_lin[i].data(), lin, s.data());
		k_m.segment(static_cast<Eigen::Index>(off), n) += s;
		marg_dims.push_back(n);
		off += static_cast<std::size_t>(n);
	}
	store_->eliminate(c.vars, marg_dims, c.sep, c.sep_dims, k_m, c.K, c.covariance);
}
}  // namespace swba::smoother
