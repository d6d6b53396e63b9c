#include "prior_only_elimination.h"

#include "conditional_mean.h"

#include <swba/factors/linear_prior.h>
#include <swba/linear/marginal.h>

#include <algorithm>
#include <stdexcept>

namespace swba::smoother::detail
{
bool PriorOnlyElimination::split(const Problem& problem, const MarginalPrior& prior,
								 const std::function<bool(VariableId)>& eliminable)
{
	const std::vector<VariableId>& vars = prior.variables();
	const std::vector<std::vector<double>>& x_lin = prior.linearization_points();
	active_.clear();
	passive_.clear();
	passive_dims_.clear();
	passive_lin_.clear();
	amanifolds_.clear();
	alin_.clear();
	reduced_factor_ = -1;
	if (vars.size() != x_lin.size()) throw std::invalid_argument("PriorOnlyElimination: one x_lin per variable");
	MarginalPrior::Partition part = prior.partition(problem, [&](VariableId v) {
		const auto& var = problem.variable(v);
		return !var.constant && var.factors.size() == 1 && *var.factors.begin() == prior.factor() && eliminable(v);
	});
	if (part.first.empty()) return false;
	for (std::size_t i : part.first)
	{
		passive_.push_back(vars[i]);
		passive_dims_.push_back(problem.variable(vars[i]).manifold->tangent_size());
		passive_lin_.push_back(x_lin[i]);
	}
	int offset = 0;
	for (std::size_t i : part.second)
	{
		const auto& manifold = problem.variable(vars[i]).manifold;
		active_.push_back({vars[i], offset, manifold->tangent_size(), x_lin[i]});
		amanifolds_.push_back(manifold);
		alin_.push_back(x_lin[i]);
		offset += manifold->tangent_size();
	}
	pcols_ = std::move(part.first_columns);
	acols_ = std::move(part.second_columns);
	return true;
}

bool PriorOnlyElimination::begin(Problem& problem, MarginalPrior& prior, double threshold,
								 const std::function<bool(VariableId)>& eliminable, bool with_covariance)
{
	if (!split(problem, prior, eliminable)) return false;
	PartitionedNormalEquations s = prior.has_information()
		? partition_normal_equations(prior.H(), prior.b(), pcols_, acols_)
		: partition_square_root(prior.J(), prior.e(), pcols_, acols_);
	reduce(problem, prior, eliminate(std::move(s), threshold, with_covariance));
	return true;
}

void PriorOnlyElimination::reduce(Problem& problem, MarginalPrior& prior, GaussianElimination c)
{
	K_ = std::move(c.conditional.K);
	k_ = std::move(c.conditional.k);
	C_ = std::move(c.conditional.covariance);
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
		// x = x_lin ⊞ δp: the prior is quadratic in δ = x ⊟ x_lin whatever the manifold (a point held
		// on a plane is stored in R³, its update is (x, y)).
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

bool PriorOnlyElimination::holds(VariableId v) const
{
	return std::find(passive_.begin(), passive_.end(), v) != passive_.end();
}

LinearConditional PriorOnlyElimination::conditional() const
{
	if (C_.rows() != K_.rows()) throw std::logic_error("PriorOnlyElimination: begun without the covariance");
	LinearConditional c;
	c.vars = passive_;
	c.dims = passive_dims_;
	for (const auto& a : active_)
	{
		c.sep.push_back(a.var);
		c.sep_dims.push_back(a.dim);
	}
	c.K = K_;
	c.covariance = C_;
	return c;
}
}  // namespace swba::smoother::detail
