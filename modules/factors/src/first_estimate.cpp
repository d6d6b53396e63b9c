#include <swba/factors/first_estimate.h>

#include <vector>

namespace swba
{
FirstEstimateFactor::FirstEstimateFactor(std::shared_ptr<const Factor> inner, std::vector<VariableId> variables,
										 std::shared_ptr<const FirstEstimateRegistry> registry)
	: Factor(inner->residual_dim(), inner->tangent_dims()),
	  inner_(std::move(inner)),
	  variables_(std::move(variables)),
	  registry_(std::move(registry))
{
	if (inner_->has_sqrt_information()) set_sqrt_information(inner_->sqrt_information());
}

bool FirstEstimateFactor::evaluate(const double* const* x, double* residual, double* const* jacobians) const
{
	if (!jacobians) return inner_->evaluate(x, residual, nullptr);
	// Called for every factor in every LM iteration: no heap allocation for the usual sizes
	// (≤ 8 variables, residual ≤ 16), a heap fallback beyond.
	constexpr int kStackVariables = 8, kStackResidual = 16;
	const int k = num_variables();
	const double* xf_stack[kStackVariables];
	std::vector<const double*> xf_heap;
	const double** xf = xf_stack;
	if (k > kStackVariables)
	{
		xf_heap.resize(k);
		xf = xf_heap.data();
	}
	bool any = false;
	for (int i = 0; i < k; i++)
	{
		auto it = registry_->find(variables_[i]);
		xf[i] = it != registry_->end() ? it->second.data() : x[i];
		any = any || it != registry_->end();
	}
	if (!any) return inner_->evaluate(x, residual, jacobians);
	if (!inner_->evaluate(x, residual, nullptr)) return false;
	// Residual at the current values (above); Jacobians at the first estimates, residual discarded.
	double scratch_stack[kStackResidual];
	std::vector<double> scratch_heap;
	double* scratch = scratch_stack;
	if (residual_dim() > kStackResidual)
	{
		scratch_heap.resize(residual_dim());
		scratch = scratch_heap.data();
	}
	return inner_->evaluate(xf, scratch, jacobians);
}
}  // namespace swba
