/** \file model_covariance.h
 * (private to the smoother module) A CovarianceRequest over the whole model the smoother holds: a
 * group may name variables the solve does not hold — the linear tail's (no longer in the problem), the
 * prior-only store's and those the prior-only elimination holds out of this solve (constant in the
 * problem). Such a group is asked of the problem's recovery as the function y = [d_v of its variables]
 * with every conditional substituted (linear_conditional.h): the tail's oldest first, then the store's,
 * then the elimination's (each one's separator holds variables of the later ones or of the problem).
 * The other groups go to the recovery as they are, so their answer is exactly what it was.
 * Exact for the linear model the smoother holds; that model is the joint of every factor so far except
 * with the store: when a state is marginalised, the store's conditional of its variables integrates the
 * state out (PriorOnlyStore::eliminate) and the state's tail conditional does not condition on them, so
 * their coupling is lost (doc/window.md, "Re-linearised poses", measures what it costs). */
#pragma once

#include "linear_tail.h"
#include "prior_only_elimination.h"
#include "prior_only_store.h"

#include <swba/nonlinear/covariance.h>

namespace swba::smoother::detail
{
class ModelCovariance
{
   public:
	/** `elimination`: the prior-only elimination of this solve, begun with its covariance (or null). */
	ModelCovariance(const CovarianceRequest& request, const Problem& problem, const LinearTail& tail,
					const PriorOnlyStore& store, const PriorOnlyElimination* elimination);
	/** What the problem's covariance recovery is asked for. */
	const CovarianceRequest& problem_request() const { return problem_; }
	/** The answer to the request, from the recovery's answer `r` to problem_request(). */
	CovarianceResult answer(CovarianceResult r) const;

   private:
	/** The groups naming held-out variables, as functions of the problem's free variables. */
	void substitute_all(std::vector<LinearExpression>& ys, const Problem& problem, const LinearTail& tail,
						const PriorOnlyStore& store, const PriorOnlyElimination* elimination) const;

	CovarianceRequest problem_;
	std::size_t num_functions_ = 0;  ///< of the request (the first of problem_.functions)
	/** Per requested group: its index in problem_.groups, or −1 − its index among the added functions. */
	std::vector<long> slot_;
	std::vector<Eigen::MatrixXd> noise_;  ///< per added function
	double seconds_ = 0;
};
}  // namespace swba::smoother::detail
