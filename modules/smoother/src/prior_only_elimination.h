/** \file prior_only_elimination.h
 * (private to the smoother module) Eliminating the variables only the marginal prior touches from a
 * step's LM solve, exactly.
 *
 * A variable no state of the window relates to any more (e.g. in a SLAM map) is connected to nothing
 * but the marginal prior r = e + J (x ⊟ x_lin). That prior is linear in its update δp = x_p ⊟ x_p,lin,
 * so for any value of the other variables a its best value is the conditional minimiser
 * δp = H_pp⁻¹ (b_p − H_pa δa) (H = JᵀJ, b = −Jᵀe), and what is left of the prior is its marginal over a:
 * H_aa − H_ap H_pp⁻¹ H_pa (the Schur complement). Solving the window with that reduced prior and the
 * prior-only variables held constant, then setting them to the conditional minimiser, reaches the same
 * optimum as solving the full problem, but every LM iteration works on a dense system of the active
 * variables only. The full prior is restored afterwards, so marginalisation and later factors see all
 * of it. */
#pragma once

#include "linear_conditional.h"

#include <swba/nonlinear/problem.h>
#include <swba/smoother/marginal_prior.h>

#include <Eigen/Core>
#include <functional>
#include <memory>
#include <vector>

namespace swba::smoother::detail
{
class PriorOnlyElimination
{
   public:
	/** If some variables of the installed `prior` satisfy `eliminable` (set back as x_lin ⊞ δp),
	 * are not constant and have no factor but the prior, uninstalls the prior, adds its marginal over the
	 * other variables and makes those prior-only variables constant; returns true. Otherwise changes
	 * nothing and returns false. The prior's information form is used when known, else (J, e).
	 * `threshold`: relative pivot cut as in swba::marginalize. `with_covariance`: keep the conditional's
	 * covariance for conditional(). */
	bool begin(Problem& problem, MarginalPrior& prior, double threshold,
			   const std::function<bool(VariableId)>& eliminable, bool with_covariance = false);
	/** After the solve: sets the prior-only variables to their conditional minimiser given the others,
	 * makes them variable again, removes the reduced prior factor and re-installs the full prior. */
	void end(Problem& problem, MarginalPrior& prior);

	/** Variables eliminated by the last begin(). */
	int num_eliminated() const { return static_cast<int>(passive_.size()); }
	/** Between begin() and end(): v is held out of the solve. */
	bool holds(VariableId v) const;
	/** Between begin(…, with_covariance) and end(): the conditional of the held-out variables given the
	 * prior's others. */
	LinearConditional conditional() const;

   private:
	/** Splits the prior's variables; false when none is prior-only. Fills pcols/acols (scalar columns). */
	bool split(const Problem& problem, const MarginalPrior& prior, const std::function<bool(VariableId)>& eliminable);
	/** Swaps the prior factor for the reduced one (the marginal of the conditional elimination `c`). */
	void reduce(Problem& problem, MarginalPrior& prior, GaussianElimination c);

	std::vector<int> pcols_, acols_;
	std::vector<std::shared_ptr<const Manifold>> amanifolds_;
	std::vector<std::vector<double>> alin_;
	struct Active
	{
		VariableId var;
		int offset;  ///< in δa
		int dim;
		std::vector<double> x_lin;
	};
	std::vector<Active> active_;
	std::vector<VariableId> passive_;
	std::vector<int> passive_dims_;
	std::vector<std::vector<double>> passive_lin_;
	Eigen::MatrixXd K_;  ///< δp = k − K δa
	Eigen::VectorXd k_;
	Eigen::MatrixXd C_;  ///< the conditional's covariance (with_covariance)
	FactorId reduced_factor_ = -1;
};
}  // namespace swba::smoother::detail
