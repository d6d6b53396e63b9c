/** \file linear_tail.h
 * (private to the smoother module) The states a fixed-lag smoother no longer re-linearises but still
 * smooths: each left the re-linearised window as the Gaussian conditional of its variables M given the
 * variables they were connected to (its separator S), in the coordinates d = x ⊟ x_lin of the
 * linearisation the marginalisation used (first estimates for S, the current values for M):
 *     d_M = k − K d_S + η,   η ~ N(0, H_MM⁻¹).
 * This is the same Schur complement that makes the marginal prior, read the other way round: the prior
 * keeps p(S), the tail keeps p(M | S), and their product is the joint the window had. The MAP of the
 * joint is the MAP of S (what the window's solve keeps computing) followed by d_M = k − K d_S, so
 * back-substitution — newest conditional first, since a separator holds only variables still in the
 * problem or that left it later — gives every tail state the estimate of a fixed-lag smoother whose
 * factors beyond the re-linearised window are frozen at their linearisation (iSAM's square-root
 * information smoother without relinearisation of the old part). Cost per step: one product of each
 * conditional's K with its separator's offset, O(dim M · dim S).
 * A change of variables in the prior (VariableChange, e.g. a re-parameterised point) rewrites the
 * columns of every conditional that holds the old variable, as it rewrites the prior's. */
#pragma once

#include "linear_conditional.h"

#include <swba/nonlinear/problem.h>
#include <swba/smoother/marginal_prior.h>

#include <Eigen/Core>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <vector>

namespace swba::smoother::detail
{
/** One state's conditional: LinearConditional's vars are the variables that left with the state (the
 * state's own included unless it was constant), rows of k and K in this order; its separator the
 * variables they were connected to, columns of K; its covariance H_MM⁻¹. */
struct TailConditional : LinearConditional
{
	double time = 0;
	VariableId state = -1;
	/** Of each of `vars`: manifold, linearisation point and current estimate. */
	std::vector<std::shared_ptr<const Manifold>> manifolds;
	std::vector<std::vector<double>> x_lin, value;
	/** Constant variables that left with the state (a fixed gauge's first pose): their values and
	 * tangent sizes (a covariance of them is zero). */
	std::map<VariableId, std::vector<double>> constants;
	std::map<VariableId, int> constant_dims;
	std::vector<std::vector<double>> sep_lin;  ///< the separator's linearisation points
	Eigen::VectorXd k;
};

class LinearTail
{
   public:
	bool empty() const { return conditionals_.empty(); }
	std::size_t size() const { return conditionals_.size(); }
	const std::deque<TailConditional>& conditionals() const { return conditionals_; }

	/** Appends the conditional of the newest state to leave the re-linearised window. */
	void push(TailConditional c);
	/** Drops the oldest conditional (its variables' estimates with it). */
	void pop_front();
	/** The current estimate (ambient) of a variable of the tail (nullptr if none holds it). */
	const std::vector<double>* value(VariableId v) const;
	/** Back-substitution, newest first: each conditional's variables at k − K d_S, with d_S from the
	 * problem's values, or the tail's for separator variables that left the problem since. Throws
	 * std::logic_error if a separator variable is in neither (a caller removed it behind the tail's back). */
	void back_substitute(const Problem& problem);
	/** The change of variables `change` (see VariableChange; its relation holds around `old_lin`, old_var's
	 * point, new_x_lin and `lin(y_i)`) in every conditional holding old_var: a conditional linearised
	 * elsewhere first moves its old_var coordinates there (exact when old_var is Euclidean), and a
	 * variable y_i not yet in its separator joins it. An empty `old_lin` means the conditionals' own
	 * points. */
	void change_variable(const VariableChange& change, const Manifold& old_manifold, const std::vector<double>& old_lin,
						 const std::function<std::vector<double>(VariableId)>& lin);

   private:
	/** First column of separator variable j in c.K. */
	static Eigen::Index column_of(const TailConditional& c, std::size_t j);
	/** The manifold of a variable of the tail (throws std::logic_error if none holds it). */
	const Manifold* manifold_of(VariableId v) const;

	std::deque<TailConditional> conditionals_;
};

/** The conditional `g` of the variables `marg` given `keep` (swba::eliminate's, with its covariance, in
 * δ = x ⊟ x_current at the values of `problem`) re-expressed around `keep_lin`: d_M = k − K d_S with
 * k = g.k + g.K s, s = x_current ⊟ keep_lin. */
TailConditional make_tail_conditional(const Problem& problem, const std::vector<VariableId>& keep,
									  const std::vector<std::vector<double>>& keep_lin,
									  const std::vector<VariableId>& marg, GaussianConditional g);
}  // namespace swba::smoother::detail
