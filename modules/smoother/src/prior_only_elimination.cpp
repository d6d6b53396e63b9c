#include "prior_only_elimination.h"

#include "conditional_mean.h"

#include <swba/factors/linear_prior.h>
#include <swba/linear/marginal.h>

#include <stdexcept>

namespace swba::smoother::detail
{
bool PriorOnlyElimination::split(const Problem& problem, const MarginalPrior& prior,
								 const std::function<bool(VariableId)>& eliminable)
{
	const std::vector<VariableId>& vars = prior.variables();
	const std::vector<std::vector<double>>& x_lin = prior.linearization_points();
	const Eigen::Index total_cols = prior.has_information() ? prior.H().cols() : prior.J().cols();
	active_.clear();
	passive_.clear();
	passive_lin_.clear();
	pcols_.clear();
	acols_.clear();
	amanifolds_.clear();
	alin_.clear();
	reduced_factor_ = -1;
	if (vars.size() != x_lin.size()) throw std::invalid_argument("PriorOnlyElimination: one x_lin per variable");
	int off = 0;
	for (std::size_t i = 0; i < vars.size(); i++)
	{
		const auto& var = problem.variable(vars[i]);
		const int n = var.manifold->tangent_size();
		const bool prior_only =
			!var.constant && var.factors.size() == 1 && *var.factors.begin() == prior.factor() && eliminable(vars[i]);
		if (prior_only)
		{
			passive_.push_back(vars[i]);
			passive_lin_.push_back(x_lin[i]);
			for (int c = 0; c < n; c++) pcols_.push_back(off + c);
		}
		else
		{
			active_.push_back({vars[i], static_cast<int>(acols_.size()), x_lin[i]});
			amanifolds_.push_back(var.manifold);
			alin_.push_back(x_lin[i]);
			for (int c = 0; c < n; c++) acols_.push_back(off + c);
		}
		off += n;
	}
	if (off != total_cols) throw std::invalid_argument("PriorOnlyElimination: the prior's size and variables disagree");
	if (passive_.empty())
	{
		active_.clear();
		return false;
	}
	return true;
}

bool PriorOnlyElimination::begin(Problem& problem, MarginalPrior& prior, double threshold,
								 const std::function<bool(VariableId)>& eliminable)
{
	if (!split(problem, prior, eliminable)) return false;
	PartitionedNormalEquations s = prior.has_information()
		? partition_normal_equations(prior.H(), prior.b(), pcols_, acols_)
		: partition_square_root(prior.J(), prior.e(), pcols_, acols_);
	reduce(problem, prior, eliminate(std::move(s), threshold));
	return true;
}

void PriorOnlyElimination::reduce(Problem& problem, MarginalPrior& prior, GaussianElimination c)
{
	K_ = std::move(c.conditional.K);
	k_ = std::move(c.conditional.k);
	prior.uninstall(problem);
	for (VariableId v : passive_) problem.set_constant(v, true);
	const MarginalizationResult& red = c.marginal;
	if (red.rank > 0)
	{
		std::vector<VariableId> avars;
		for (const auto& a : active_) avars.push_back(a.var);
		reduced_factor_ = problem.add_factor(
			std::make_shared<LinearPriorFactor>(red.J, red.e, std::move(alin_), std::move(amanifolds_)), std::move(avars));
	}
}

void PriorOnlyElimination::end(Problem& problem, MarginalPrior& prior)
{
	if (passive_.empty()) return;
	// δa = x_a ⊟ x_a,lin, then δp = k − K δa.
	Eigen::VectorXd da(K_.cols());
	for (const auto& a : active_)
		problem.variable(a.var).manifold->minus(problem.value(a.var), a.x_lin.data(), da.data() + a.offset);
	ConditionalMean dp(k_);
	dp.condition(K_, da);
	int off = 0;
	for (std::size_t i = 0; i < passive_.size(); i++)
	{
		// x = x_lin ⊞ δp: the prior is quadratic in δ = x ⊟ x_lin whatever the manifold (a planar
		// landmark's storage is R³, its update (x, y)).
		const Manifold& m = *problem.variable(passive_[i]).manifold;
		problem.set_value(passive_[i], dp.value(m, passive_lin_[i], off).data());
		off += m.tangent_size();
		problem.set_constant(passive_[i], false);
	}
	if (reduced_factor_ >= 0) problem.remove_factor(reduced_factor_);
	reduced_factor_ = -1;
	active_.clear();
	passive_.clear();
	passive_lin_.clear();
	prior.install(problem);
}
}  // namespace swba::smoother::detail
