#include <swba/nonlinear/linearization.h>

#include <map>

namespace swba
{
DenseLinearSystem linearize_dense(const Problem& problem, const std::vector<VariableId>& order,
								  const std::vector<FactorId>& factors_in)
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
