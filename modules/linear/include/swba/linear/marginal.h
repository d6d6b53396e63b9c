/** \file marginalization.h
 * Marginalisation of a linearised Gaussian: given the normal equations H δ = b (b = −Jᵀr) over a
 * set of scalar coordinates, eliminate the coordinates `marg` by a Schur complement and return the
 * prior on the coordinates `keep`:
 *     H* = H_kk − H_km H_mm⁻¹ H_mk,   b* = b_k − H_km H_mm⁻¹ b_m,
 * and its square-root form (J, e) with ½‖e + J δ_k‖² = ½ δ_kᵀ H* δ_k − b*ᵀ δ_k + const, i.e.
 * JᵀJ = H*, Jᵀe = −b*.
 *
 * Numerics (why these decompositions): H_mm (small: the leaving pose and the landmarks leaving with
 * it) is inverted through a self-adjoint eigen-decomposition with the relative threshold, so a
 * rank-deficient marginalised block (an unobservable direction of the dropped variables) is
 * pseudo-inverted instead of blowing up. H* is symmetrised and factored by a pivoted LDLᵀ
 * (H* = Pᵀ L D Lᵀ P, Eigen::LDLT): J = √D Lᵀ P and e = −√D⁻¹ L⁻¹ P b* over the pivots
 * D_i > rel_threshold·max(D), so the prior claims no information along numerically unobservable
 * directions. LDLᵀ rather than an eigen-decomposition: H* is dense over all landmarks of a SLAM
 * window (hundreds of unknowns) and is re-factored at every step; LDLᵀ costs n³/3 against ~9n³ and
 * gives the same prior where nothing is truncated (basalt keeps a square-root form for the same
 * reason). */
#pragma once

#include <Eigen/Core>
#include <vector>

namespace swba
{
struct MarginalizationResult
{
	Eigen::MatrixXd H;  ///< Schur complement H* over `keep` (symmetrised)
	Eigen::VectorXd b;  ///< b* over `keep`
	Eigen::MatrixXd J;  ///< rank × |keep| square-root information (JᵀJ = H up to truncation)
	Eigen::VectorXd e;  ///< rank residual at the linearisation point
	int rank = 0;       ///< pivots kept
};

/** Fills m.J, m.e and m.rank from m.H, m.b (already symmetric) by the truncated pivoted LDLᵀ above; for
 * callers that form the Schur complement themselves (e.g. when a plain Cholesky square root fails on a
 * rank-deficient H*). */
void square_root_form(MarginalizationResult& m, double rel_threshold = 1e-12);

/** Eliminates `marg` from (H, b); `keep` and `marg` are disjoint index lists into H (any index not
 * listed is ignored). Throws std::invalid_argument on bad indices or sizes. */
MarginalizationResult marginalize(const Eigen::MatrixXd& H, const Eigen::VectorXd& b,
								  const std::vector<int>& keep, const std::vector<int>& marg,
								  double rel_threshold = 1e-12);
}  // namespace swba
