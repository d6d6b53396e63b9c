/** \file covariance.h
 * Marginal covariances of a Problem's Gaussian approximation at its current values: Σ = H⁻¹ with
 * H = JᵀJ the undamped normal equations (whitened, robust losses as the solver applies them) in the
 * variables' tangent coordinates (a pose: right perturbation T = T̂·Exp(δ), δ = [ρ, ω]).
 *
 * Only the requested blocks are recovered, from the factorisation the solver uses (Schur complement
 * of the eliminated group, reduced system by dense LLT or CHOLMOD). Groups of kept variables, when
 * they ask for more than a few dozen coordinates and CHOLMOD holds the factor, are read from the
 * inverse on the factor's pattern (selected_inverse.h: one pass, about Σ_j |L_*j|²); the others cost
 * one solve against the factor per tangent coordinate (n² for a dense reduced system of size n, nnz(L)
 * for CHOLMOD's), then the back-substitution of the eliminated variables they ask for. Never a dense
 * inverse of the whole system.
 *
 * Constant variables have zero covariance (the gauge they fix: with the first pose constant every
 * covariance is relative to it). A problem whose H is singular (a free gauge) has none: hold a
 * variable constant and, if wanted, ask for the minimum-norm gauge through CovarianceRequest::gauge. */
#pragma once

#include <swba/nonlinear/problem.h>
#include <swba/nonlinear/solver.h>

#include <Eigen/Core>
#include <map>
#include <string>
#include <vector>

namespace swba
{
/** A linear function y = Σ_v A_v δ_v of the variables' tangent coordinates: A_v (rows × tangent size of
 * v) by variable, every block with the same rows; a constant variable's block counts as zero. */
using LinearFunction = std::map<VariableId, Eigen::MatrixXd>;

struct CovarianceRequest
{
	/** One joint covariance per group, over its variables' tangent coordinates in the listed order
	 * (a single variable: its marginal). */
	std::vector<std::vector<VariableId>> groups;
	/** One covariance Cov(y) = A Σ Aᵀ per function: rows(A) solves, however many variables A spans
	 * (a group over them would cost one solve per tangent coordinate). */
	std::vector<LinearFunction> functions;
	/** Optional gauge directions N_v (tangent × k) of every non-constant variable: when given, the
	 * covariances are moved to the minimum-norm gauge Nᵀδ = 0 along these directions,
	 * Σ_N = Q Σ Qᵀ with Q = I − N (NᵀN)⁻¹ Nᵀ (exact when H N = 0: the problem is held by constant
	 * variables only, whose rows of N count as zero displacement). k extra solves. */
	std::map<VariableId, Eigen::MatrixXd> gauge;

	bool empty() const { return groups.empty() && functions.empty(); }
};

struct CovarianceResult
{
	/** False when H is not positive definite over the non-constant variables (blocks then empty). */
	bool ok = false;
	std::string message;
	std::vector<Eigen::MatrixXd> blocks;     ///< per group
	std::vector<Eigen::MatrixXd> functions;  ///< per function
	int solves = 0;                       ///< solves against the factor (none for blocks read from the selected inverse)
	double seconds = 0;                   ///< factorisation + solves (+ linearisation for marginal_covariance)
};

/** The covariances of `request` at the current values, from a fresh linearisation and one undamped
 * factorisation with the linear solver `options` chooses (the one solve() would use). */
CovarianceResult marginal_covariance(Problem& problem, const CovarianceRequest& request,
									 const SolverOptions& options = {});

/** solve() that, after the LM loop, recovers the covariances of `request` at the solution from the
 * normal equations the loop last assembled there (no new linearisation: one undamped factorisation
 * and the solves). `covariance` is left with ok = false when the solution is not usable. */
Summary solve(Problem& problem, const SolverOptions& options, const CovarianceRequest& request,
			  CovarianceResult* covariance);
}  // namespace swba
