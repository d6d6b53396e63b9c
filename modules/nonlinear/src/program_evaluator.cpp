#include "program_evaluator.h"

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

void ProgramEvaluator::evaluate_factor(int f, bool want_jacobians)
{
	const auto& fs = program_.factor(f);
	const int k = static_cast<int>(fs.values.size());
	double* r = residuals_.data() + fs.residual_offset;
	double* jac[16];
	int cols[16];
	std::vector<double*> jac_heap;
	double** J = jac;
	int* C = cols;
	std::vector<int> cols_heap;
	if (k > 16)
	{
		jac_heap.resize(k);
		cols_heap.resize(k);
		J = jac_heap.data();
		C = cols_heap.data();
	}
	for (int s = 0; s < k; s++)
	{
		J[s] = (want_jacobians && fs.jacobian_offset[s] >= 0) ? jacobians_.data() + fs.jacobian_offset[s] : nullptr;
		C[s] = fs.factor->tangent_dims()[s];
	}
	const bool ok = fs.factor->evaluate_whitened(fs.values.data(), r, want_jacobians ? J : nullptr);
	bool finite = ok;
	if (ok)
		for (int i = 0; i < fs.m; i++) finite = finite && std::isfinite(r[i]);
	if (!finite)
	{
		valid_[f] = 0;
		factor_cost_[f] = 0;
		std::fill(r, r + fs.m, 0.0);
		if (want_jacobians)
			for (int s = 0; s < k; s++)
				if (J[s]) std::fill(J[s], J[s] + fs.m * C[s], 0.0);
		return;
	}
	valid_[f] = 1;
	if (fs.loss)
		factor_cost_[f] = apply_loss(*fs.loss, fs.m, r, k, C, want_jacobians ? J : nullptr);
	else
	{
		double s2 = 0;
		for (int i = 0; i < fs.m; i++) s2 += r[i] * r[i];
		factor_cost_[f] = 0.5 * s2;
	}
}

double ProgramEvaluator::evaluate(bool want_jacobians, int* dropped, int* newly_dropped)
{
	const int nf = program_.num_factors();
	if (newly_dropped) valid_before_ = valid_;
#pragma omp parallel for schedule(dynamic, 256) num_threads(num_threads_) if (nf > kParallelMin)
	for (int f = 0; f < nf; f++) evaluate_factor(f, want_jacobians);
	double cost = 0;
	int nd = 0;
	for (int f = 0; f < nf; f++)
	{
		cost += factor_cost_[f];
		nd += valid_[f] ? 0 : 1;
	}
	if (dropped) *dropped = nd;
	if (newly_dropped)
	{
		*newly_dropped = 0;
		for (int f = 0; f < nf; f++) *newly_dropped += (valid_before_[f] && !valid_[f]) ? 1 : 0;
	}
	return cost;
}
}  // namespace swba::detail
