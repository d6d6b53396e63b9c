/** \file linear_conditional.h
 * (private to the smoother module) Covariances through Gaussian conditionals. The smoother holds its
 * model as the solve's problem (factors and the marginal prior) times Gaussian conditionals of the
 * variables the solve does not hold — the linear tail's, the prior-only store's, those the prior-only
 * elimination holds out of one solve — each of variables M given a separator S:
 *     d_M = k − K d_S + η,   η ~ N(0, C) independent of d_S and of every newer conditional,
 * in the coordinates d = x ⊟ x_lin of its own linearisation. A separator holds variables of the problem
 * or of a conditional made later, so the joint covariance follows newest conditional first from the
 * problem's covariance Σ over the separators' variables:
 *     Cov(d_M) = C + K Σ_SS Kᵀ,   Cov(d_M, d_V) = −K Σ_SV.
 * substitute() runs the same sums from the other end, for one wanted function y = A d (e.g. one pose):
 * oldest conditional first, d_M in y is replaced by its conditional, which moves y's coefficients to
 * the separator (A_S ← A_S − A_M K) and adds A_M C A_Mᵀ to the covariance of an independent noise;
 * once no variable outside the problem is left, Cov(y) = A Σ Aᵀ + noise, with A Σ Aᵀ from rows(y)
 * solves against the problem's factor (CovarianceRequest::functions). Cost O(rows(y) · dim M · dim S)
 * per conditional, where the newest-first form keeps the joint covariance of every variable an older
 * conditional references (the whole map under the SLAM policy: O(dim S²) per conditional, and that
 * many solves for Σ).
 * Coordinates: the conditionals are around their linearisation points (the separators' first
 * estimates), Σ in the tangent at the current values; on a manifold the two agree to first order
 * (exactly for Euclidean variables): this is the covariance of the linearised model, as the prior's is. */
#pragma once

#include <swba/nonlinear/problem.h>

#include <Eigen/Core>
#include <map>
#include <vector>

namespace swba::smoother::detail
{
/** What a covariance needs of a Gaussian conditional d_M = k − K d_S + η, η ~ N(0, covariance). */
struct LinearConditional
{
	std::vector<VariableId> vars;  ///< M: rows of K in this order
	std::vector<int> dims;         ///< their tangent sizes
	std::vector<VariableId> sep;   ///< S: columns of K in this order
	std::vector<int> sep_dims;
	Eigen::MatrixXd K;
	Eigen::MatrixXd covariance;  ///< C
};

/** y = Σ_v A_v d_v + ε, ε ~ N(0, noise) independent of every d_v. */
struct LinearExpression
{
	std::map<VariableId, Eigen::MatrixXd> coefficients;  ///< A_v: rows(y) × tangent size of v
	Eigen::MatrixXd noise;                               ///< rows(y) × rows(y)
};

/** y as the function of d's with all its rows, the identity on the variables `vars` (sizes `dims`). */
LinearExpression identity_expression(const std::vector<VariableId>& vars, const std::vector<int>& dims);

/** Substitutes the conditional `c` into `y` (nothing if y has no coefficient on c's variables). Substitute
 * a conditional only after every one whose separator holds its variables (the tail's oldest first). */
void substitute(LinearExpression& y, const LinearConditional& c);
}  // namespace swba::smoother::detail
