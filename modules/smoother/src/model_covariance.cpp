#include "model_covariance.h"

#include <swba/core/timing.h>

#include <algorithm>
#include <functional>
#include <set>
#include <stdexcept>

namespace swba::smoother::detail
{
namespace
{
/** Tangent size of v: the problem's variable, else the tail's. */
int tangent_size_in_model(VariableId v, const Problem& problem, const LinearTail& tail)
{
	if (problem.has_variable(v)) return problem.variable(v).manifold->tangent_size();
	for (const auto& c : tail.conditionals())
	{
		for (std::size_t i = 0; i < c.vars.size(); i++)
			if (c.vars[i] == v) return c.dims[i];
		if (const auto it = c.constant_dims.find(v); it != c.constant_dims.end()) return it->second;
	}
	throw std::invalid_argument("covariance request: a variable neither in the problem nor in the linear tail");
}

/** The variables with a coefficient in some of `ys` that `in` holds. */
std::vector<VariableId> variables_in(const std::vector<LinearExpression>& ys, const std::function<bool(VariableId)>& in)
{
	std::set<VariableId> out;
	for (const auto& y : ys)
		for (const auto& [v, A] : y.coefficients)
			if (in(v)) out.insert(v);
	return {out.begin(), out.end()};
}
}  // namespace

ModelCovariance::ModelCovariance(const CovarianceRequest& request, const Problem& problem, const LinearTail& tail,
								 const PriorOnlyStore& store, const PriorOnlyElimination* elimination)
	: problem_(request), num_functions_(request.functions.size())
{
	const auto t0 = SteadyClock::now();
	const auto held_out = [&](VariableId v) {
		return !problem.has_variable(v) || store.contains(v) || (elimination && elimination->holds(v));
	};
	problem_.groups.clear();
	std::vector<LinearExpression> ys;
	for (const auto& g : request.groups)
	{
		if (std::none_of(g.begin(), g.end(), held_out))
		{
			slot_.push_back(static_cast<long>(problem_.groups.size()));
			problem_.groups.push_back(g);
			continue;
		}
		std::vector<int> dims;
		for (VariableId v : g) dims.push_back(tangent_size_in_model(v, problem, tail));
		slot_.push_back(-1 - static_cast<long>(ys.size()));
		ys.push_back(identity_expression(g, dims));
	}
	if (ys.empty()) return;
	substitute_all(ys, problem, tail, store, elimination);
	for (auto& y : ys)
	{
		problem_.functions.push_back(std::move(y.coefficients));
		noise_.push_back(std::move(y.noise));
	}
	seconds_ = seconds_since(t0);
}

void ModelCovariance::substitute_all(std::vector<LinearExpression>& ys, const Problem& problem, const LinearTail& tail,
									 const PriorOnlyStore& store, const PriorOnlyElimination* elimination) const
{
	for (const auto& c : tail.conditionals())
		for (auto& y : ys) substitute(y, c);
	const std::vector<VariableId> stored = variables_in(ys, [&](VariableId v) { return store.contains(v); });
	if (!stored.empty())
	{
		const LinearConditional c = store.conditional(stored);
		for (auto& y : ys) substitute(y, c);
	}
	if (elimination)
	{
		const LinearConditional c = elimination->conditional();
		for (auto& y : ys) substitute(y, c);
	}
	// What is left are the problem's variables and constants, which have no covariance (a fixed gauge's
	// pose, in the problem or gone with a tail state).
	for (auto& y : ys)
		for (auto it = y.coefficients.begin(); it != y.coefficients.end();)
		{
			const bool in_problem = problem.has_variable(it->first);
			if (!in_problem && !tail.value(it->first))
				throw std::logic_error("ModelCovariance: a separator variable is neither in the problem nor in a conditional");
			it = !in_problem || problem.is_constant(it->first) ? y.coefficients.erase(it) : std::next(it);
		}
}

CovarianceResult ModelCovariance::answer(CovarianceResult r) const
{
	if (noise_.empty()) return r;
	r.seconds += seconds_;
	if (!r.ok)
	{
		r.blocks.clear();
		r.functions.clear();
		return r;
	}
	std::vector<Eigen::MatrixXd> blocks;
	for (long s : slot_)
	{
		if (s >= 0)
			blocks.push_back(r.blocks[static_cast<std::size_t>(s)]);
		else
		{
			const auto f = static_cast<std::size_t>(-1 - s);
			const Eigen::MatrixXd& solved = r.functions[num_functions_ + f];  // empty: only constants left
			blocks.push_back(solved.size() == 0 ? noise_[f] : Eigen::MatrixXd(solved + noise_[f]));
		}
	}
	r.blocks = std::move(blocks);
	r.functions.resize(num_functions_);
	return r;
}
}  // namespace swba::smoother::detail
