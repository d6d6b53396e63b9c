/** \file positive_definite.h
 * Repairing a symmetric matrix that should be positive definite (an information matrix read from a
 * file) by eigenvalue clipping.
 *
 * The nearest symmetric positive *semi*-definite matrix to A in the Frobenius norm is obtained by
 * symmetrising, S = (A + Aᵀ)/2, and setting the negative eigenvalues of S to zero (Higham 1988,
 * "Computing a nearest symmetric positive semidefinite matrix"). A zero eigenvalue gives a singular
 * information (no Cholesky factor, an unconstrained direction), so the eigenvalues are clipped at a
 * positive floor instead:
 *
 *   floor = relative_floor · λ_max(S),   default relative_floor = 1e-6.
 *
 * Why relative: the entries of a pose-graph information mix units (1/m², 1/rad², 1/(m·rad)), so no
 * absolute floor fits every file; a floor proportional to λ_max is invariant to rescaling the matrix
 * (repair(c·A) = c·repair(A)) and bounds the condition number of the repaired matrix by
 * 1/relative_floor = 1e6, which keeps its Cholesky factor and the normal equations it enters
 * well-conditioned in double precision (rounding in the rebuild is ≈ 1e-16·λ_max, ten orders below
 * the floor, so the result is numerically positive definite). Among matrices with eigenvalues
 * ≥ floor, clipping is again the Frobenius-nearest one. A direction the file gave negative
 * information thus gets the weight of the weakest direction allowed: it barely constrains the solution. */
#pragma once

#include <Eigen/Core>

namespace swba
{
/** Default floor of the repaired eigenvalues, relative to the largest one (see the file comment). */
constexpr double kPositiveDefiniteRelativeFloor = 1e-6;

/** What repair_positive_definite did. */
struct PositiveDefiniteRepair
{
	Eigen::MatrixXd matrix;      ///< the result: symmetric positive definite
	bool repaired = false;       ///< false: the input was symmetric positive definite and is returned as is
	/** Eigenvalues of the symmetrised input; computed only when repaired (else 0). */
	double min_eigenvalue = 0, max_eigenvalue = 0;
	int clipped = 0;  ///< eigenvalues raised to the floor (0 when not repaired)
};

/** The nearest (Frobenius) symmetric matrix to `a` whose eigenvalues are all ≥ relative_floor ·
 * λ_max((a + aᵀ)/2). If the symmetrised matrix already has a Cholesky factor (Eigen::LLT succeeds),
 * it is returned unchanged — bit-identical to `a` when `a` is symmetric — and `repaired` is false:
 * valid input is never altered, however ill-conditioned. Otherwise the symmetrised matrix is
 * eigen-decomposed (Eigen::SelfAdjointEigenSolver), eigenvalues below the floor are set to it and
 * the matrix is rebuilt (and symmetrised exactly).
 * Throws std::invalid_argument if `a` is not square or not finite, or relative_floor ∉ (0, 1];
 * std::domain_error if no eigenvalue is positive (λ_max ≤ 0: nothing to scale a floor by — the
 * matrix carries no information to keep). */
PositiveDefiniteRepair repair_positive_definite(const Eigen::MatrixXd& a,
												 double relative_floor = kPositiveDefiniteRelativeFloor);

/** repair_positive_definite(a, relative_floor).matrix. */
Eigen::MatrixXd nearest_positive_definite(const Eigen::MatrixXd& a,
										  double relative_floor = kPositiveDefiniteRelativeFloor);
}  // namespace swba
