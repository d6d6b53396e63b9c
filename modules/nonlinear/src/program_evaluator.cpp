#include "program_evaluator.h"

#include <swba/core/scratch.h>

#include <algorithm>
#include <cmath>

namespace swba::detail
{
ProgramEvaluator::ProgramEvaluator(const Program& program, int num_threads)
	: program_(program), num_threads_(std::max(1, num_threads))
{
	residuals_.assign(program.residual_size(), 0.0);
	jacobians_.assign(program.jacobian_size(), 0.0);
	valid_.assign(program.num_factors(), 1);
	factor_cost_.assign(program.num_factors(), 0.0);
}

void ProgramEvaluator::evaluate_factor(int f, bool want_jacobians, const Outputs& out)
{
	const auto& fs = program_.factor(f);
	const int k = static_cast<int>(fs.values.size());
	double* r = out.residuals->data() + fs.residual_offset;
	Scratch<double*, 16> jac(static_cast<std::size_t>(k));
	Scratch<int, 16> dims(static_cast<std::size_t>(k));
	double** J = jac.data();
	int* C = dims.data();
	for (int s = 0; s < k; s++)
	{
		J[s] = (want_jacobians && fs.jacobian_offset[s] >= 0) ? jacobians_.data() + fs.jacobian_offset[s] : nullptr;
		C[s] = fs.factor->tangent_dims()[s];
	}
	const bool ok = fs.factor->evaluate_whitened(fs.values.data(), r, want_jacobians ? J : nullptr);
	bool finite = ok;
	if (ok)
		for (int i = 0; i < fs.m; i++) finite = finite && std::isfinite(r[i]);
	double& cost = (*out.cost)[f];
	if (!finite)
	{
		(*out.valid)[f] = 0;
		cost = 0;
		std::fill(r, r + fs.m, 0.0);
		if (want_jacobians)
			for (int s = 0; s < k; s++)
				if (J[s]) std::fill(J[s], J[s] + fs.m * C[s], 0.0);
		return;
	}
	(*out.valid)[f] = 1;
	if (fs.loss)
		cost = apply_loss(*fs.loss, fs.m, r, k, C, want_jacobians ? J : nullptr);
	else
	{
		double s2 = 0;
		for (int i = 0; i < fs.m; i++) s2 += r[i] * r[i];
		cost = 0.5 * s2;
	}
}

double ProgramEvaluator::evaluate_all(bool want_jacobians, const Outputs& out, int* dropped)
{
	const int nf = program_.num_factors();
#pragma omp parallel for schedule(dynamic, 256) num_threads(num_threads_) if (nf > kParallelMin)
	for (int f = 0; f < nf; f++) evaluate_factor(f, want_jacobians, out);
	double cost = 0;
	int nd = 0;
	for (int f = 0; f < nf; f++)
	{
		cost += (*out.cost)[f];
		nd += (*out.valid)[f] ? 0 : 1;
	}
	if (dropped) *dropped = nd;
	return cost;
}

double ProgramEvaluator::linearize(int* dropped)
{
	return evaluate_all(true, {&residuals_, &valid_, &factor_cost_}, dropped);
}

TrialEvaluation ProgramEvaluator::evaluate_trial()
{
	trial_residuals_.resize(residuals_.size());
	trial_valid_.resize(valid_.size());
	trial_cost_.resize(factor_cost_.size());
	TrialEvaluation t;
	t.cost = evaluate_all(false, {&trial_residuals_, &trial_valid_, &trial_cost_}, &t.dropped);
	for (int f = 0; f < program_.num_factors(); f++)
	{
		if (valid_[f] && !trial_valid_[f])
		{
			t.left.push_back(f);
			t.left_cost += factor_cost_[f];
		}
		else if (!valid_[f] && trial_valid_[f])
		{
			t.entered++;
			t.entered_cost += trial_cost_[f];
		}
	}
	if (!t.left.empty()) t.stranded = count_stranded(t.left);
	return t;
}

namespace
{
bool any_valid(const std::vector<FactorSlot>& slots, const std::vector<char>& valid)
{
	return std::any_of(slots.begin(), slots.end(), [&](const FactorSlot& fs) { return valid[fs.first] != 0; });
}
}  // namespace

int ProgramEvaluator::count_stranded(const std::vector<int>& left) const
{
	std::vector<char> seen_kept(program_.num_kept(), 0), seen_elim(program_.num_elim(), 0);
	int stranded = 0;
	for (int f : left)
	{
		const auto& fs = program_.factor(f);
		for (size_t s = 0; s < fs.kind.size(); s++)
		{
			const int i = fs.index[s];
			if (fs.kind[s] == kKeptSlot && !seen_kept[i])
			{
				seen_kept[i] = 1;
				stranded += any_valid(program_.kept_factors(i), trial_valid_) ? 0 : 1;
			}
			else if (fs.kind[s] == kEliminatedSlot && !seen_elim[i])
			{
				seen_elim[i] = 1;
				stranded += any_valid(program_.elim_factors(i), trial_valid_) ? 0 : 1;
			}
		}
	}
	return stranded;
}

int ProgramEvaluator::count_unconstrained() const
{
	int n = 0;
	for (int a = 0; a < program_.num_kept(); a++) n += any_valid(program_.kept_factors(a), valid_) ? 0 : 1;
	for (int l = 0; l < program_.num_elim(); l++) n += any_valid(program_.elim_factors(l), valid_) ? 0 : 1;
	return n;
}
}  // namespace swba::detail
