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
 * it) is applied through SymmetricInverse, a Cholesky solve when it is clearly positive definite and
 * otherwise a self-adjoint eigen-decomposition with the relative threshold, so a rank-deficient
 * marginalised block (an unobservable direction of the dropped variables) is pseudo-inverted instead
 * of blowing up. H* is symmetrised and kept in square-root form: J = Lᵀ from a
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

#include <Eigen/Cholesky>
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

/** Normal equations split by two disjoint index sets: p (to be eliminated) and a (kept). */
struct PartitionedNormalEquations
{
	Eigen::MatrixXd Hpp, Hpa, Haa;
	Eigen::VectorXd bp, ba;
};

/** The blocks of (H, b) at the indices p and a, in the listed orders (plain copies). */
PartitionedNormalEquations partition_normal_equations(const Eigen::MatrixXd& H, const Eigen::VectorXd& b,
													  const std::vector<int>& p, const std::vector<int>& a);

/** The blocks of (H, b) with a = the first `num_keep` coordinates and p = the rest. Throws
 * std::invalid_argument unless H is n×n, b n and 0 ≤ num_keep ≤ n. */
PartitionedNormalEquations partition_leading(const Eigen::MatrixXd& H, const Eigen::VectorXd& b, int num_keep);

/** The blocks of H = JᵀJ and b = −Jᵀe for the columns p and a of the square-root form (J, e), formed
 * from the gathered columns (symmetric rank updates for Hpp and Haa): cheaper than forming all of JᵀJ
 * when only these blocks are needed. Throws std::invalid_argument when e and J disagree. */
PartitionedNormalEquations partition_square_root(const Eigen::MatrixXd& J, const Eigen::VectorXd& e,
												 const std::vector<int>& p, const std::vector<int>& a);

/** The one policy for applying the inverse of a symmetric positive semi-definite block A: a Cholesky
 * solve when A is clearly positive definite (every pivot L_ii² above rel_threshold times the largest;
 * a landmark observed with range and bearing always is), else truncated_pseudo_inverse (a rank-deficient
 * block, e.g. an unobservable direction of the dropped variables, is cut instead of blowing up). */
class SymmetricInverse
{
   public:
	SymmetricInverse(const Eigen::MatrixXd& A, double rel_threshold);
	/** A⁻¹ B. */
	Eigen::MatrixXd solve(const Eigen::MatrixXd& B) const;
	/** A⁻¹ (symmetric to rounding). */
	Eigen::MatrixXd inverse() const;

   private:
	Eigen::LLT<Eigen::MatrixXd> llt_;
	bool cholesky_ = false;
	Eigen::MatrixXd pseudo_inverse_;
};

/** A Gaussian conditional of the eliminated coordinates p given the kept ones a, in the coordinates
 * of the normal equations it came from: δp = k − K δa + η, η ~ N(0, covariance). */
struct GaussianConditional
{
	Eigen::MatrixXd K;           ///< Hpp⁻¹ Hpa
	Eigen::VectorXd k;           ///< Hpp⁻¹ bp
	Eigen::MatrixXd covariance;  ///< Hpp⁻¹ (only when asked for)
};

/** What eliminating p leaves: the conditional of p given a and the marginal over a. */
struct GaussianElimination
{
	GaussianConditional conditional;
	/** Haa − Hpaᵀ K and ba − Hpaᵀ k, symmetrised, in square-root form: J = Lᵀ from a blocked Cholesky
	 * (Eigen::LLT; upper triangular in the given order, e = −L⁻¹ b*) when H* is clearly positive
	 * definite (every pivot above threshold times the larger of its largest pivot, `scale` and the
	 * largest diagonal of Haa), else square_root_form's truncated pivoted Cholesky of the same H* (a
	 * rank-deficient H*, e.g. a free gauge or the anchor poses of inverse-depth landmarks, see
	 * doc/window.md). Empty (rank 0) when a is empty. */
	MarginalizationResult marginal;
};

/** The one Gaussian elimination (GTSAM's eliminate returning {conditional, marginal}): eliminates p
 * from `s`, Hpp⁻¹ applied once through SymmetricInverse; the conditional's covariance Hpp⁻¹ is formed
 * only `with_covariance`. Used by the marginal prior, the linear tail and the prior-only variables. */
GaussianElimination eliminate(PartitionedNormalEquations s, double threshold, bool with_covariance = false,
							  double scale = 0);

/** eliminate(partition_normal_equations(H, b, marg, keep)).marginal: `keep` and `marg` are disjoint
 * index lists into H (any index not listed is ignored). Throws std::invalid_argument on bad indices or
 * sizes. */
MarginalizationResult marginalize(const Eigen::MatrixXd& H, const Eigen::VectorXd& b,
								  const std::vector<int>& keep, const std::vector<int>& marg,
								  double rel_threshold = 1e-12);

/** eliminate(partition_leading(H, b, num_keep), threshold, false, scale).marginal: keep = the first
 * `num_keep` coordinates, marg = the rest. */
MarginalizationResult marginalize_leading(const Eigen::MatrixXd& H, const Eigen::VectorXd& b, int num_keep,
										  double threshold, double scale = 0);
}  // namespace swba
