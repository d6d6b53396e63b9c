#include <swba/core/numeric_diff.h>

#include <stdexcept>

namespace swba
{
double JacobianComparison::max_relative_error() const
{
	double worst = 0;
	for (size_t i = 0; i < analytic.size(); i++)
	{
		const double scale = std::max(1.0, numeric[i].cwiseAbs().maxCoeff());
		worst = std::max(worst, (analytic[i] - numeric[i]).cwiseAbs().maxCoeff() / scale);
	}
	return worst;
}

JacobianComparison compare_jacobians(const Factor& factor, const std::vector<const double*>& x,
									 const std::vector<const Manifold*>& manifolds, double h)
{
	const int k = factor.num_variables();
	const int m = factor.residual_dim();
	if (static_cast<int>(x.size()) != k || static_cast<int>(manifolds.size()) != k)
		throw std::invalid_argument("compare_jacobians: one value and one manifold per variable");
	JacobianComparison out;
	std::vector<double*> jac_ptrs(k);
	for (int i = 0; i < k; i++)
	{
		out.analytic.emplace_back(m, factor.tangent_dims()[i]);
		jac_ptrs[i] = out.analytic.back().data();
	}
	Eigen::VectorXd r0(m);
	if (!factor.evaluate(x.data(), r0.data(), jac_ptrs.data()))
		throw std::runtime_error("compare_jacobians: factor not evaluable at x");
	for (int i = 0; i < k; i++)
	{
		const int n = factor.tangent_dims()[i];
		RowMajorMatrix N(m, n);
		std::vector<double> xp(manifolds[i]->ambient_size()), xm(xp.size());
		for (int c = 0; c < n; c++)
		{
			Eigen::VectorXd d = Eigen::VectorXd::Zero(n);
			d[c] = h;
			manifolds[i]->plus(x[i], d.data(), xp.data());
			d[c] = -h;
			manifolds[i]->plus(x[i], d.data(), xm.data());
			std::vector<const double*> xs = x;
			Eigen::VectorXd rp(m), rm(m);
			xs[i] = xp.data();
			if (!factor.evaluate(xs.data(), rp.data(), nullptr))
				throw std::runtime_error("compare_jacobians: factor not evaluable at x+h");
			xs[i] = xm.data();
			if (!factor.evaluate(xs.data(), rm.data(), nullptr))
				throw std::runtime_error("compare_jacobians: factor not evaluable at x-h");
			N.col(c) = (rp - rm) / (2 * h);
		}
		out.numeric.push_back(N);
	}
	return out;
}
}  // namespace swba
