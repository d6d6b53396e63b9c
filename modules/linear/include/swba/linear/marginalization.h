/** \file marginalization.h
 * Marginalisation of a linearised Gaussian: given the normal equations H δ = b (b = −Jᵀr) over a
 * set of scalar coordinates, eliminate the coordinates `marg` by a Schur complement and return the
 * prior on the coordinates `keep`:
 *     H* = H_kk − H_km H_mm⁻¹ H_mk,   b* = b_k − H_km H_mm⁻¹ b_m,
 * and its square-root form (J, e) with ½‖e + J δ_k‖² = ½ δ_kᵀ H* δ_k − b*ᵀ δ_k + const, i.e.
 * JᵀJ = H*, Jᵀe = −b*.
 *
 * Numerics (why these decompositions): H_mm is inverted through a self-adjoint eigen-decomposition
 * with the same relative threshold, so a rank-deficient marginalised block (an unobservable
 * direction of the dropped variables) is pseudo-inverted instead of blowing up; H* is symmetrised,
 * then eigen-decomposed (SelfAdjointEigenSolver, exact for symmetric matrices) and eigenvalues
 * λ ≤ rel_threshold·λ_max are dropped — J = √Λ Vᵀ, e = −√Λ⁻¹ Vᵀ b* over the kept eigenpairs — so the
 * prior never claims information along (numerically) unobservable directions. */
#pragma once

#include <Eigen/Core>
#include <vector>

namespace swba
{
struct MarginalizationResult
{
	Eigen::MatrixXd H;  ///< Schur complement H* over `keep` (symmetrised)
	Eigen::VectorXd b;  ///< b* over `keep`
	Eigen::MatrixXd J;  ///< rank × |keep| square-root information
	Eigen::VectorXd e;  ///< rank residual at the linearisation point
	int rank = 0;       ///< eigenvalues kept
};

/** Eliminates `marg` from (H, b); `keep` and `marg` are disjoint index lists into H (any index not
 * listed is ignored). Throws std::invalid_argument on bad indices or sizes. */
MarginalizationResult marginalize(const Eigen::MatrixXd& H, const Eigen::VectorXd& b,
								  const std::vector<int>& keep, const std::vector<int>& marg,
								  double rel_threshold = 1e-12);
}  // namespace swba
