#include <swba/factors/first_estimate.h>

#include <swba/core/scratch.h>

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
	// Called for every factor in every LM iteration: no heap allocation for the usual sizes.
	const int k = num_variables();
	Scratch<const double*, 8> first(static_cast<std::size_t>(k));
	const double** xf = first.data();
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
	Scratch<double, 16> discarded(static_cast<std::size_t>(residual_dim()));
	return inner_->evaluate(xf, discarded.data(), jacobians);
}
}  // namespace swba
