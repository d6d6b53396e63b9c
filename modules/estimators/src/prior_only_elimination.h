/** \file prior_only_elimination.h
 * (private to the estimators module) Eliminating the variables only the marginal prior touches from a
 * window's LM solve, exactly.
 *
 * With the SLAM policy every landmark stays in the state, but a landmark that no pose of the window
 * observes any more is connected to nothing but the marginal prior r = e + J (x ⊟ x_lin). That prior is
 * linear in such a (Euclidean) landmark, so for any value of the other variables a its best value is the
 * conditional minimiser δp = H_pp⁻¹ (b_p − H_pa δa) (H = JᵀJ, b = −Jᵀe), and what is left of the prior
 * is its marginal over a: H_aa − H_ap H_pp⁻¹ H_pa (the Schur complement). Solving the window with that
 * reduced prior and the prior-only landmarks held constant, then setting them to the conditional
 * minimiser, reaches the same optimum as solving the full problem, but every LM iteration works on a
 * dense system of (active landmarks + window poses) instead of (every landmark ever seen + poses).
 * The full prior is restored afterwards, so marginalisation and re-observations see the whole map. */
#pragma once

#include <swba/linear/marginal.h>
#include <swba/nonlinear/problem.h>

#include <memory>
#include <Eigen/Core>
#include <functional>
#include <vector>

namespace swba::estimators::detail
{
class PriorOnlyElimination
{
   public:
	/** If some variables of the prior (a LinearPriorFactor `prior_factor` over `vars` with J, e, x_lin)
	 * satisfy `eliminable` (Euclidean variables: landmarks), are not constant and have no factor but the
	 * prior, removes the prior factor, adds its marginal over the other variables and makes those
	 * prior-only variables constant; returns true. Otherwise changes nothing and returns false.
	 * `threshold`: relative pivot cut as in swba::marginalize. */
	bool begin(Problem& problem, FactorId prior_factor, const std::vector<VariableId>& vars, const Eigen::MatrixXd& J,
			   const Eigen::VectorXd& e, const std::vector<std::vector<double>>& x_lin, double threshold,
			   const std::function<bool(VariableId)>& eliminable);
	/** As above, with the prior's information H = JᵀJ and b = −Jᵀe already known (saves forming them). */
	bool begin(Problem& problem, FactorId prior_factor, const std::vector<VariableId>& vars, const Eigen::MatrixXd& H,
			   const Eigen::VectorXd& b, const std::vector<std::vector<double>>& x_lin, double threshold,
			   const std::function<bool(VariableId)>& eliminable, bool information_form);
	/** After the solve: sets the prior-only variables to their conditional minimiser given the others,
	 * makes them variable again and removes the reduced prior factor (the caller re-adds the full one). */
	void end(Problem& problem);

	/** Variables eliminated by the last begin(). */
	int num_eliminated() const { return static_cast<int>(passive_.size()); }

   private:
	/** Splits the prior's variables; false when none is prior-only. Fills pcols/acols (scalar columns). */
	bool split(const Problem& problem, FactorId prior_factor, const std::vector<VariableId>& vars,
			   const std::vector<std::vector<double>>& x_lin, const std::function<bool(VariableId)>& eliminable,
			   Eigen::Index total_cols);
	/** Given the blocks of H and b: computes K, k, swaps the prior factor for the reduced one. */
	void reduce(Problem& problem, FactorId prior_factor, PartitionedNormalEquations s, double threshold);

	std::vector<int> pcols_, acols_;
	std::vector<std::shared_ptr<const Manifold>> amanifolds_;
	std::vector<std::vector<double>> alin_;
	struct Active
	{
		VariableId var;
		int offset;  ///< in δa
		std::vector<double> x_lin;
	};
	std::vector<Active> active_;
	std::vector<VariableId> passive_;
	std::vector<std::vector<double>> passive_lin_;
	Eigen::MatrixXd K_;  ///< δp = k − K δa
	Eigen::VectorXd k_;
	FactorId reduced_factor_ = -1;
};
/** Dense normal equations H δ = b (b = −Jᵀr, whitened, robust losses applied as the solver does) of
 * `factors` at the current values over the variables `order` (others held fixed), like
 * swba::linearize_dense, but block by block without the stacked Jacobian, and with one factor, the
 * marginal prior, entered from its known information: a LinearPriorFactor r = e + J (x ⊟ x_lin) with
 * constant J contributes H_prior = JᵀJ and b_prior − H_prior (x ⊟ x_lin). O(Σ factor blocks + n²)
 * instead of O(rows·n²). */
struct DenseNormalSystem
{
	Eigen::MatrixXd H;
	Eigen::VectorXd b;
	std::vector<int> offsets;  ///< of each variable of `order` (size order.size() + 1)
};
struct KnownPrior
{
	FactorId factor = -1;
	const std::vector<VariableId>* vars = nullptr;
	const std::vector<std::vector<double>>* x_lin = nullptr;
	const Eigen::MatrixXd* H = nullptr;  ///< JᵀJ over vars' tangent coordinates
	const Eigen::VectorXd* b = nullptr;  ///< −Jᵀe
};
DenseNormalSystem dense_normal_system(const Problem& problem, const std::vector<VariableId>& order,
									  const std::vector<FactorId>& factors, const KnownPrior& prior);

}  // namespace swba::estimators::detail
