#include <swba/estimators/first_estimate.h>

#include <Eigen/Core>

namespace swba::estimators
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
	const int k = num_variables();
	std::vector<const double*> xf(x, x + k);
	bool any = false;
	for (int i = 0; i < k; i++)
	{
		auto it = registry_->find(variables_[i]);
		if (it != registry_->end())
		{
			xf[i] = it->second.data();
			any = true;
		}
	}
	if (!any) return inner_->evaluate(x, residual, jacobians);
	if (!inner_->evaluate(x, residual, nullptr)) return false;
	Eigen::VectorXd scratch(residual_dim());
	return inner_->evaluate(xf.data(), scratch.data(), jacobians);
}
}  // namespace swba::estimators
