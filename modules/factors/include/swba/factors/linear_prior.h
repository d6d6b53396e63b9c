/** \file linear_prior.h
 * The marginalisation prior kept as a linearised residual (VINS-Mono / basalt style):
 *     r(x) = e + Σ_i J_i · (x_i ⊟ x_i,lin),
 * over the variables that remained after a Schur complement. J (rank × Σ tangent dims) and e come from
 * swba::marginalize; x_lin are the values at the time of marginalisation. The Jacobian reported for
 * each variable is the constant J_i (the first-estimate Jacobian: d(x ⊟ x_lin)/dδ is taken as I, exact
 * at x = x_lin), so the prior is a fixed quadratic in the tangent-space offsets. */
#pragma once

#include <swba/core/factor.h>
#include <swba/core/manifold.h>

#include <Eigen/Core>
#include <memory>
#include <vector>

namespace swba
{
class LinearPriorFactor final : public Factor
{
   public:
	/** `J` has one column block per variable (sizes = manifolds' tangent sizes), `e` rank rows,
	 * `x_lin[i]` the ambient linearisation value of variable i. Throws std::invalid_argument on
	 * inconsistent sizes or a zero-rank prior. */
	LinearPriorFactor(Eigen::MatrixXd J, Eigen::VectorXd e, std::vector<std::vector<double>> x_lin,
					  std::vector<std::shared_ptr<const Manifold>> manifolds);

	bool evaluate(const double* const* x, double* residual, double* const* jacobians) const override;
	/** The reported Jacobians are the constant J_i. */
	bool constant_jacobian() const override { return true; }

	const Eigen::MatrixXd& J() const { return J_; }
	const Eigen::VectorXd& e() const { return e_; }
	const std::vector<std::vector<double>>& x_lin() const { return x_lin_; }
	const std::vector<std::shared_ptr<const Manifold>>& manifolds() const { return manifolds_; }
	/** Column offset of variable i in J. */
	int offset(int i) const { return offsets_[i]; }

   private:
	static std::vector<int> dims_of(const std::vector<std::shared_ptr<const Manifold>>& m);
	Eigen::MatrixXd J_;
	Eigen::VectorXd e_;
	std::vector<std::vector<double>> x_lin_;
	std::vector<std::shared_ptr<const Manifold>> manifolds_;
	std::vector<int> offsets_;
};
}  // namespace swba
