/** \file dense_normal_system.h
 * (private to the smoother module) The linearisation of a marginalisation step: dense normal
 * equations H δ = b (b = −Jᵀr, whitened, robust losses applied as the solver does) of `factors` at the
 * current values over the variables `order` (others held fixed), accumulated block by block without
 * the stacked Jacobian, and with one factor, the marginal prior, entered from its
 * known information: a LinearPriorFactor r = e + J (x ⊟ x_lin) with constant J contributes
 * H_prior = JᵀJ and b_prior − H_prior (x ⊟ x_lin). O(Σ factor blocks + n²) instead of O(rows·n²). */
#pragma once

#include <swba/nonlinear/problem.h>
#include <swba/smoother/marginal_prior.h>

#include <Eigen/Core>
#include <vector>

namespace swba::smoother::detail
{
struct DenseNormalSystem
{
	Eigen::MatrixXd H;
	Eigen::VectorXd b;
	std::vector<int> offsets;  ///< of each variable of `order` (size order.size() + 1)
	/** Factors that could not be evaluated at the current values (residual undefined or not finite):
	 * left out of H and b, so their information is lost. */
	int unevaluable = 0;
};

/** `known_prior`: the installed marginal prior with known information (its factor is then taken from
 * H and b instead of being linearised), or null. */
DenseNormalSystem dense_normal_system(const Problem& problem, const std::vector<VariableId>& order,
									  const std::vector<FactorId>& factors, const MarginalPrior* known_prior);
}  // namespace swba::smoother::detail
