/** \file linearization.h
 * Dense linearisation of (part of) a Problem: the stacked whitened Jacobian and residual, and the
 * normal equations H = JᵀJ, b = −Jᵀr over a chosen variable order. For small systems only: tests,
 * marginalisation of a window's oldest state, null-space analysis. Robust losses are applied with
 * the same correction as the solver. Cost O(m·n + n²·m) for m residual rows, n tangent dimensions. */
#pragma once

#include <swba/nonlinear/problem.h>

#include <Eigen/Core>
#include <vector>

namespace swba
{
struct DenseLinearSystem
{
	Eigen::MatrixXd J;  ///< rows: residuals of the chosen factors; cols: tangent coordinates of `order`
	Eigen::VectorXd r;
	Eigen::MatrixXd H;  ///< JᵀJ
	Eigen::VectorXd b;  ///< −Jᵀr
	std::vector<int> offsets;  ///< column offset of each variable of `order` (size order.size()+1)
	int num_dropped = 0;       ///< factors that could not be evaluated (left out)
};

/** Linearises `factors` (all factors of the problem if empty) at the current values over the
 * variables `order`. Variables a factor touches that are not in `order` are held fixed (their
 * Jacobian columns are omitted). */
DenseLinearSystem linearize_dense(const Problem& problem, const std::vector<VariableId>& order,
								  const std::vector<FactorId>& factors = {});
}  // namespace swba
