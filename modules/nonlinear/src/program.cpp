#include "program.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace swba::detail
{
std::set<VariableId> linked_eliminable_variables(const Problem& problem)
{
	std::set<VariableId> linked;
	std::vector<VariableId> elim;
	for (const auto& [fid, fe] : problem.factors())
	{
		elim.clear();
		for (VariableId v : fe.variables)
		{
			const auto& var = problem.variables().at(v);
			if (!var.constant && var.group == Group::Eliminable) elim.push_back(v);
		}
		if (elim.size() > 1) linked.insert(elim.begin(), elim.end());
	}
	return linked;
}

namespace
{
/** The tangent size shared by every variable of `list`, 0 if they differ or the list is empty. */
int uniform_tangent(const std::vector<OrderedVariable>& list)
{
	int uniform = list.empty() ? 0 : list[0].tangent;
	for (const auto& v : list)
		if (v.tangent != uniform) uniform = 0;
	return uniform;
}
}  // namespace

Program::Program(Problem& problem, bool use_schur, const std::set<VariableId>& keep) : problem_(problem)
{
	const Placement where = order_variables(use_schur, keep);
	var_factors_kept_.resize(kept_.size());
	var_factors_elim_.resize(elim_.size());
	for (const auto& [fid, fe] : problem_.factors()) add_factor(fid, fe, where);
	uniform_kept_ = uniform_tangent(kept_);
	uniform_elim_ = uniform_tangent(elim_);
}

Program::Placement Program::order_variables(bool use_schur, const std::set<VariableId>& keep)
{
	// Kept variables first (by id), then eliminated ones (by id); constants removed.
	Placement where;
	for (auto& [id, cv] : problem_.variables())
	{
		auto& v = const_cast<Problem::Variable&>(cv);
		if (v.constant)
		{
			num_constant_++;
			where[id] = {kConstantSlot, -1};
			continue;
		}
		const int t = v.manifold->tangent_size();
		if (use_schur && v.group == Group::Eliminable && keep.count(id) == 0)
		{
			where[id] = {kEliminatedSlot, static_cast<int>(elim_.size())};
			elim_.push_back({id, &v, t, elim_dim_});
			elim_dim_ += t;
		}
		else
		{
			where[id] = {kKeptSlot, static_cast<int>(kept_.size())};
			kept_.push_back({id, &v, t, kept_dim_});
			kept_dim_ += t;
		}
	}
	return where;
}

void Program::add_factor(FactorId id, const Problem::FactorEntry& entry, const Placement& where)
{
	FactorSlotInfo fs;
	fs.factor = entry.factor.get();
	fs.loss = entry.loss.get();
	fs.m = entry.factor->residual_dim();
	fs.residual_offset = residual_size_;
	residual_size_ += fs.m;
	int n_elim = 0;
	const int fidx = static_cast<int>(factors_.size());
	const size_t k = entry.variables.size();
	fs.values.reserve(k);
	fs.kind.reserve(k);
	fs.index.reserve(k);
	fs.jacobian_offset.reserve(k);
	for (size_t s = 0; s < k; s++)
	{
		const auto [kind, index] = where.at(entry.variables[s]);
		fs.values.push_back(problem_.value(entry.variables[s]));
		fs.kind.push_back(kind);
		fs.index.push_back(index);
		if (kind == kConstantSlot)
		{
			fs.jacobian_offset.push_back(-1);
			continue;
		}
		fs.jacobian_offset.push_back(jacobian_size_);
		jacobian_size_ += fs.m * entry.factor->tangent_dims()[s];
		if (kind == kEliminatedSlot)
		{
			n_elim++;
			var_factors_elim_[index].push_back({fidx, static_cast<int>(s)});
		}
		else
			var_factors_kept_[index].push_back({fidx, static_cast<int>(s)});
	}
	if (n_elim > 1)
		throw std::invalid_argument("solve: factor " + std::to_string(id) +
									" connects two eliminable variables; Schur elimination needs "
									"landmarks that only connect to kept variables");
	factors_.push_back(std::move(fs));
}

void Program::save_values()
{
	backup_.clear();
	for (const auto* list : {&kept_, &elim_})
		for (const auto& v : *list) backup_.insert(backup_.end(), v.var->value.begin(), v.var->value.end());
}

void Program::restore_values()
{
	size_t pos = 0;
	for (auto* list : {&kept_, &elim_})
		for (auto& v : *list)
		{
			std::copy_n(backup_.data() + pos, v.var->value.size(), v.var->value.data());
			pos += v.var->value.size();
		}
}

void Program::apply_step(const Eigen::VectorXd& delta)
{
	for (auto& v : kept_) v.var->manifold->plus(v.var->value.data(), delta.data() + v.offset, v.var->value.data());
	for (auto& v : elim_)
		v.var->manifold->plus(v.var->value.data(), delta.data() + kept_dim_ + v.offset, v.var->value.data());
}

double Program::values_norm() const
{
	double s = 0;
	for (const auto* list : {&kept_, &elim_})
		for (const auto& v : *list)
			for (double x : v.var->value) s += x * x;
	return std::sqrt(s);
}
}  // namespace swba::detail
