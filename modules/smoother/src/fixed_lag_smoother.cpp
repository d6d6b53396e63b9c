#include <swba/smoother/fixed_lag_smoother.h>

#include "dense_normal_system.h"
#include "prior_only_elimination.h"

#include <swba/linear/marginal.h>

namespace swba::smoother
{
FixedLagSmoother::FixedLagSmoother(const FixedLagSmootherOptions& options) : opt_(options) {}

FactorId FixedLagSmoother::add_factor(std::shared_ptr<const Factor> factor, std::vector<VariableId> variables,
									  std::shared_ptr<const LossFunction> loss)
{
	if (opt_.first_estimate_jacobians)
		factor = std::make_shared<FirstEstimateFactor>(std::move(factor), variables, first_estimates_);
	return problem_.add_factor(std::move(factor), std::move(variables), std::move(loss));
}

void FixedLagSmoother::add_state(double time, VariableId var) { states_.push_back({time, var}); }

bool FixedLagSmoother::over_lag() const { return opt_.lag > 0 && static_cast<int>(states_.size()) > opt_.lag; }

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

void FixedLagSmoother::change_prior_variable(const VariableChange& change)
{
	prior_.change_variable(problem_, change);
	if (opt_.first_estimate_jacobians) (*first_estimates_)[change.new_var] = change.first_estimate;
	prior_.install(problem_);
}

UpdateSummary FixedLagSmoother::update(const std::function<bool(VariableId)>& eliminable,
										const CovarianceRequest& covariance)
{
	UpdateSummary out;
	detail::PriorOnlyElimination elimination;
	const bool reduced = opt_.eliminate_prior_only && prior_.installed() &&
						 elimination.begin(problem_, prior_, opt_.marginalization_threshold, eliminable);
	out.solver = swba::solve(problem_, opt_.solver, covariance, &out.covariance);
	if (reduced)
	{
		out.prior_only_eliminated = elimination.num_eliminated();
		elimination.end(problem_, prior_);
	}
	return out;
}

Summary FixedLagSmoother::solve(const SolverOptions& options) { return swba::solve(problem_, options); }

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
	MarginalizationResult m = marginalize_leading(sys.H, sys.b, num_keep, opt_.marginalization_threshold);
	// Those factors and variables are replaced by the new prior.
	if (prior_.installed() && factors.count(prior_.factor())) prior_.forget_factor();  // removed below
	for (FactorId f : factors) problem_.remove_factor(f);
	for (VariableId v : marg) remove_variable(v);
	states_.pop_front();
	// The new prior is stored around the first estimates of its variables (their current values without FEJ).
	std::vector<std::vector<double>> x_lin;
	for (VariableId v : keep)
	{
		const double* x = linearization_point(v);
		x_lin.emplace_back(x, x + problem_.variable(v).manifold->ambient_size());
	}
	prior_.reset(problem_, std::move(keep), std::move(m), std::move(x_lin));
	return {std::move(factors), sys.unevaluable};
}
}  // namespace swba::smoother
