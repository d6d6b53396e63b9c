/** \file marginal.h
 * Marginalisation of a linearised Gaussian as pure functions over the normal equations (H, b) or the
 * square-root form (J, e) plus index sets; no estimator state. Given H δ = b (b = −Jᵀr) over a set of
 * scalar coordinates, eliminating the coordinates `marg` by a Schur complement leaves the prior on the
 * coordinates `keep`:
 *     H* = H_kk − H_km H_mm⁻¹ H_mk,   b* = b_k − H_km H_mm⁻¹ b_m,
 * kept in square-root form (J, e) with ½‖e + J δ_k‖² = ½ δ_kᵀ H* δ_k − b*ᵀ δ_k + const, i.e.
 * JᵀJ = H*, Jᵀe = −b*.
 *
 * Numerics (why these decompositions): H_mm (small: the leaving pose and the landmarks leaving with
 * it) is inverted through a self-adjoint eigen-decomposition with the relative threshold, so a
 * rank-deficient marginalised block (an unobservable direction of the dropped variables) is
 * pseudo-inverted instead of blowing up. H* is symmetrised and kept in square-root form: J = Lᵀ from a
 * Cholesky factor when H* is clearly positive definite, else from a rank-revealing pivoted Cholesky
 * (Pᵀ H* P ≈ L Lᵀ, pivoting on the largest remaining diagonal, LAPACK's dpstrf scheme) stopped at the
 * first pivot not above rel_threshold times the largest diagonal of the kept block before elimination:
 * the prior claims no information along numerically unobservable directions (a free gauge, the
 * anchor poses of inverse-depth landmarks), and a Schur complement that cancels to rounding noise
 * has rank 0. When anything is truncated, the returned H and b are those of the truncated square
 * root (H = JᵀJ, b = −Jᵀe): every form of the result describes one quadratic. Not Eigen's LDLᵀ: it
 * pivots on the original diagonal, so after a numerically zero pivot its later pivots are ratios of
 * rounding noise (measured on a SLAM prior: max|H − JᵀJ| = 151 with ‖H‖ ≈ 1e8). Not an
 * eigen-decomposition: H* is dense over all landmarks of a SLAM window (hundreds of unknowns) and is
 * re-factored at every step; a Cholesky costs n³/3 against ~9n³ (basalt keeps a square-root form for
 * the same reason). */
#pragma once

#include <Eigen/Core>
#include <vector>

namespace swba
{
struct MarginalizationResult
{
	Eigen::MatrixXd H;  ///< Schur complement H* over `keep` (symmetrised); JᵀJ when truncated
	Eigen::VectorXd b;  ///< b* over `keep`; −Jᵀe when truncated
	Eigen::MatrixXd J;  ///< rank × |keep| square-root information (JᵀJ = H)
	Eigen::VectorXd e;  ///< rank residual at the linearisation point
	int rank = 0;       ///< pivots kept
};

/** The thresholded pseudo-inverse of a symmetric positive semi-definite H (n ≥ 1): V diag(1/λ_i) Vᵀ
 * from the self-adjoint eigen-decomposition of ½(H + Hᵀ), over the eigenvalues λ_i > 0 and
 * > rel_threshold·max(λ); the others (numerically unobservable directions) get 0 instead of blowing
 * up. An eigen-decomposition because it is applied to small blocks (a leaving pose and its landmarks)
 * where robustness to rank deficiency matters more than its ~9n³ cost. */
Eigen::MatrixXd truncated_pseudo_inverse(const Eigen::MatrixXd& H, double rel_threshold);

/** Fills m.J, m.e and m.rank from m.H, m.b (already symmetric) by the truncated pivoted Cholesky above,
 * and, when it truncates, replaces m.H and m.b by JᵀJ and −Jᵀe; for callers that form the Schur
 * complement themselves. `scale`: the reference magnitude of the cut when larger than m.H's largest
 * diagonal (the system m.H was reduced from). Throws std::invalid_argument when H is not n×n or b
 * not n. */
void square_root_form(MarginalizationResult& m, double rel_threshold = 1e-12, double scale = 0);

/** Eliminates `marg` from (H, b); `keep` and `marg` are disjoint index lists into H (any index not
 * listed is ignored). H_mm through truncated_pseudo_inverse, the square root by square_root_form.
 * Throws std::invalid_argument on bad indices or sizes. */
MarginalizationResult marginalize(const Eigen::MatrixXd& H, const Eigen::VectorXd& b,
								  const std::vector<int>& keep, const std::vector<int>& marg,
								  double rel_threshold = 1e-12);

/** marginalize() for keep = the first `num_keep` coordinates of (H, b) and marg = the rest, with the
 * square root from a blocked Cholesky (Eigen::LLT; J = Lᵀ upper triangular in the given order,
 * e = −L⁻¹ b*) when H* is clearly positive definite (every pivot L_ii² above threshold times the
 * larger of its largest pivot, `scale` and the largest diagonal of H's kept block): the same prior as
 * marginalize(), faster on the dense priors of a SLAM window. Otherwise (LLT fails or a pivot is tiny:
 * a rank-deficient H*, e.g. a free gauge or the anchor poses of inverse-depth landmarks, see
 * doc/window.md) the square root is square_root_form's truncated pivoted Cholesky of the same H* (the
 * Schur complement is not redone). Throws std::invalid_argument unless H is n×n, b n and
 * 0 ≤ num_keep ≤ n. */
MarginalizationResult marginalize_leading(const Eigen::MatrixXd& H, const Eigen::VectorXd& b, int num_keep,
										  double threshold, double scale = 0);

/** Normal equations split by two disjoint index sets: p (to be eliminated) and a (kept). */
struct PartitionedNormalEquations
{
	Eigen::MatrixXd Hpp, Hpa, Haa;
	Eigen::VectorXd bp, ba;
};

/** The blocks of (H, b) at the indices p and a, in the listed orders (plain copies). */
PartitionedNormalEquations partition_normal_equations(const Eigen::MatrixXd& H, const Eigen::VectorXd& b,
													  const std::vector<int>& p, const std::vector<int>& a);

/** The blocks of H = JᵀJ and b = −Jᵀe for the columns p and a of the square-root form (J, e), formed
 * from the gathered columns (symmetric rank updates for Hpp and Haa): cheaper than forming all of JᵀJ
 * when only these blocks are needed. Throws std::invalid_argument when e and J disagree. */
PartitionedNormalEquations partition_square_root(const Eigen::MatrixXd& J, const Eigen::VectorXd& e,
												 const std::vector<int>& p, const std::vector<int>& a);

/** Eliminating p from partitioned normal equations, kept as the conditional δp = k − K δa (the
 * minimiser over δp for a given δa) and the marginal over a. */
struct ConditionalElimination
{
	Eigen::MatrixXd K;  ///< Hpp⁻¹ Hpa
	Eigen::VectorXd k;  ///< Hpp⁻¹ bp
	/** Haa − Hpaᵀ K and ba − Hpaᵀ k in the square-root form of marginalize_leading (num_keep = all);
	 * left empty (rank 0) when a is empty. */
	MarginalizationResult marginal;
};

/** Eliminates p (Hpp non-empty) from `s`. Hpp⁻¹ is applied by a Cholesky solve when Hpp is clearly
 * positive definite (every pivot above threshold·max; a landmark observed with range and bearing
 * always is), else through truncated_pseudo_inverse (a rank-deficient block is cut, not inverted).
 * The marginal's rank cut is relative to Haa before the elimination. */
ConditionalElimination eliminate_conditional(PartitionedNormalEquations s, double threshold);
}  // namespace swba
