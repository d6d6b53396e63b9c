/** \file dense_linearization.h
 * (tests only) Dense linearisation of (part of) a Problem: the stacked whitened Jacobian and residual,
 * and the normal equations H = JᵀJ, b = −Jᵀr over a chosen variable order — the straightforward
 * reference the tests hold the solver, the marginalisation and the covariances against. Robust losses
 * are applied with the same correction as the solver. Cost O(m·n + n²·m) for m residual rows, n tangent
 * dimensions. (The library's own dense normal equations, for marginalisation, are built block by block
 * in modules/smoother.) */
#pragma once

#include <swba/core/loss.h>
#include <swba/nonlinear/problem.h>

#include <Eigen/Core>
#include <map>
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

/** Linearises `factors_in` (all factors of the problem if empty) at the current values over the
 * variables `order`. Variables a factor touches that are not in `order` are held fixed (their
 * Jacobian columns are omitted). */
inline DenseLinearSystem linearize_dense(const Problem& problem, const std::vector<VariableId>& order,
										 const std::vector<FactorId>& factors_in = {})
{
	DenseLinearSystem out;
	std::map<VariableId, int> col;
	out.offsets.push_back(0);
	for (VariableId v : order)
	{
		col[v] = static_cast<int>(out.offsets.size()) - 1;
		out.offsets.push_back(out.offsets.back() + problem.variable(v).manifold->tangent_size());
	}
	std::vector<FactorId> factors = factors_in;
	if (factors.empty())
		for (const auto& [fid, fe] : problem.factors()) factors.push_back(fid);
	int rows = 0;
	for (FactorId f : factors) rows += problem.factor(f).factor->residual_dim();
	const int n = out.offsets.back();
	out.J.setZero(rows, n);
	out.r.setZero(rows);
	int row = 0;
	for (FactorId f : factors)
	{
		const auto& fe = problem.factor(f);
		const int m = fe.factor->residual_dim();
		const int k = fe.factor->num_variables();
		std::vector<const double*> xs;
		std::vector<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> jac(k);
		std::vector<double*> jp(k);
		std::vector<int> cols(k);
		for (int s = 0; s < k; s++)
		{
			xs.push_back(problem.value(fe.variables[s]));
			cols[s] = fe.factor->tangent_dims()[s];
			jac[s].setZero(m, cols[s]);
			jp[s] = jac[s].data();
		}
		Eigen::VectorXd r(m);
		if (!fe.factor->evaluate_whitened(xs.data(), r.data(), jp.data()) || !r.allFinite())
		{
			out.num_dropped++;
			row += m;
			continue;
		}
		if (fe.loss) apply_loss(*fe.loss, m, r.data(), k, cols.data(), jp.data());
		out.r.segment(row, m) = r;
		for (int s = 0; s < k; s++)
		{
			auto it = col.find(fe.variables[s]);
			if (it == col.end()) continue;
			out.J.block(row, out.offsets[it->second], m, cols[s]) = jac[s];
		}
		row += m;
	}
	out.H = out.J.transpose() * out.J;
	out.b = -out.J.transpose() * out.r;
	return out;
}
}  // namespace swba
