/** \file conditional_mean.h
 * (private to the smoother module) The mean of a Gaussian conditional d = k − Σ_j K_j δ_j in the
 * coordinates d = x ⊟ x_lin of its variables, and their values x = x_lin ⊞ d: the one place the
 * prior-only elimination, the prior-only store and the linear tail evaluate a conditional. */
#pragma once

#include <swba/core/manifold.h>

#include <Eigen/Core>
#include <utility>
#include <vector>

namespace swba::smoother::detail
{
class ConditionalMean
{
   public:
	explicit ConditionalMean(Eigen::VectorXd k) : d_(std::move(k)) {}
	/** d −= K_j δ_j: the conditioning variables j at the offset δ_j from their linearisation point. */
	void condition(const Eigen::Ref<const Eigen::MatrixXd>& K_j, const Eigen::VectorXd& delta_j)
	{
		d_.noalias() -= K_j * delta_j;
	}
	/** x_lin ⊞ d[offset, offset + tangent size): one variable's value. */
	std::vector<double> value(const Manifold& m, const std::vector<double>& x_lin, Eigen::Index offset) const
	{
		std::vector<double> x(x_lin.size());
		m.plus(x_lin.data(), d_.data() + offset, x.data());
		return x;
	}
	const Eigen::VectorXd& offsets() const { return d_; }

   private:
	Eigen::VectorXd d_;
};
}  // namespace swba::smoother::detail
