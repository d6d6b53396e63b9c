#include "linear_conditional.h"

#include <numeric>
#include <stdexcept>

namespace swba::smoother::detail
{
LinearExpression identity_expression(const std::vector<VariableId>& vars, const std::vector<int>& dims)
{
	const Eigen::Index rows = std::accumulate(dims.begin(), dims.end(), Eigen::Index{0});
	LinearExpression y;
	y.noise = Eigen::MatrixXd::Zero(rows, rows);
	for (std::size_t i = 0, off = 0; i < vars.size(); off += static_cast<std::size_t>(dims[i++]))
	{
		Eigen::MatrixXd& A = y.coefficients[vars[i]];
		if (A.size() == 0) A = Eigen::MatrixXd::Zero(rows, dims[i]);
		A.middleRows(static_cast<Eigen::Index>(off), dims[i]) += Eigen::MatrixXd::Identity(dims[i], dims[i]);
	}
	return y;
}

void substitute(LinearExpression& y, const LinearConditional& c)
{
	const Eigen::Index rows = y.noise.rows();
	if (c.K.rows() != c.covariance.rows() || c.vars.size() != c.dims.size() || c.sep.size() != c.sep_dims.size())
		throw std::invalid_argument("substitute: the conditional's sizes disagree");
	// A_M: y's coefficients on the conditional's variables, which leave y.
	Eigen::MatrixXd A_M = Eigen::MatrixXd::Zero(rows, c.K.rows());
	bool any = false;
	for (std::size_t i = 0, off = 0; i < c.vars.size(); off += static_cast<std::size_t>(c.dims[i++]))
	{
		const auto it = y.coefficients.find(c.vars[i]);
		if (it == y.coefficients.end()) continue;
		A_M.middleCols(static_cast<Eigen::Index>(off), c.dims[i]) = it->second;
		y.coefficients.erase(it);
		any = true;
	}
	if (!any) return;
	y.noise.noalias() += A_M * c.covariance * A_M.transpose();
	const Eigen::MatrixXd A_S = A_M * c.K;
	for (std::size_t j = 0, off = 0; j < c.sep.size(); off += static_cast<std::size_t>(c.sep_dims[j++]))
	{
		Eigen::MatrixXd& A = y.coefficients[c.sep[j]];
		if (A.size() == 0) A = Eigen::MatrixXd::Zero(rows, c.sep_dims[j]);
		A -= A_S.middleCols(static_cast<Eigen::Index>(off), c.sep_dims[j]);
	}
}
}  // namespace swba::smoother::detail
