/** \file first_estimate.h
 * First-estimate Jacobians (FEJ): a factor decorator that evaluates the residual at the current
 * values but the Jacobians with every variable that has a frozen first estimate replaced by it. The
 * frozen values live in a registry shared by all decorated factors of a window (read-only during a
 * solve). This keeps the marginal prior and the factors linearised at one consistent point per state,
 * so the prior adds no information along unobservable (gauge) directions. */
#pragma once

#include <swba/core/factor.h>
#include <swba/nonlinear/problem.h>

#include <map>
#include <memory>
#include <vector>

namespace swba
{
/** Frozen linearisation points by variable. */
using FirstEstimateRegistry = std::map<VariableId, std::vector<double>>;

class FirstEstimateFactor final : public Factor
{
   public:
	/** `variables` are the problem variables the factor will be added on (same order). */
	FirstEstimateFactor(std::shared_ptr<const Factor> inner, std::vector<VariableId> variables,
						std::shared_ptr<const FirstEstimateRegistry> registry);
	bool evaluate(const double* const* x, double* residual, double* const* jacobians) const override;

   private:
	std::shared_ptr<const Factor> inner_;
	std::vector<VariableId> variables_;
	std::shared_ptr<const FirstEstimateRegistry> registry_;
};
}  // namespace swba
