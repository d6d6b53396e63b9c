// Internal: the damped solve (H + λD) δ = −g, D = clamp(diag H), of assembled normal equations by
// Schur elimination of the eliminated variables (Ceres's SchurEliminator): per eliminated variable the
// damped inverse H_ll⁻¹, the reduced system S over the kept variables, assembled block row by block
// row with kernels templated on the block sizes, its Cholesky factorisation (dense or CHOLMOD) and the
// back-substitution of the eliminated variables. Without eliminated variables S is the damped H_pp.
#pragma once

#include <swba/linear/block_cholesky.h>

#include "normal_equations.h"
#include "program.h"

#include <Eigen/Core>
#include <memory>
#include <vector>

namespace swba::detail
{
class SchurEliminator
{
   public:
	/** Builds the pattern of the reduced system: the H_pp blocks and every pair of kept variables that
	 * share an eliminated one. `sparse` chooses the back end (CHOLMOD or dense LLT). */
	SchurEliminator(const Program& program, const NormalEquations& equations, bool sparse, int num_threads);

	bool sparse() const { return sparse_; }
	/** Chooses the back end for the reduced system (only before the first solve_damped). */
	void set_sparse(bool sparse);
	/** Fraction of the upper block triangle of the reduced system that is structurally non-zero. */
	double reduced_block_fill() const;

	/** Solves (H + λ D) δ = −g, D = clamp(diag H, min_diag, max_diag); δ over [kept; eliminated].
	 * False if the damped system is not positive definite (or the solution is not finite). */
	bool solve_damped(double lambda, double min_diag, double max_diag, Eigen::VectorXd& delta);
	/** After a successful solve_damped: solves the same system for the right-hand sides X (columns over
	 * [kept; eliminated]), in place (X_p = S⁻¹ (B_p − Σ_l H_pl H_ll⁻¹ B_l), X_l = H_ll⁻¹ (B_l − H_lp X_p)),
	 * reusing the factorisation, one pass through the factor for all columns. Only the eliminated
	 * variables with `back[l]` set are back-substituted (the others are left at zero); `back` empty: all. */
	void solve_factorized(Eigen::MatrixXd& X, const std::vector<char>& back = {}) const;
	/** After a successful solve_damped: S⁻¹, the covariance of the kept variables, on the pattern of its
	 * sparse factor; nullptr when solving `columns` columns is cheaper (BlockCholesky::selected_inverse). */
	std::unique_ptr<SelectedInverse> selected_inverse(int columns) const;

   private:
	void build_reduced_pattern();
	void build_schur_terms();

	/** Damped inverse H_ll⁻¹ of one eliminated variable; false (and a zero inverse) if not SPD. */
	template <int NL>
	bool invert_damped_ll(int l, double lambda, double min_diag, double max_diag);
	/** Block row a of the reduced system S (blocks (a, b ≥ a)) and its right-hand side, streamed
	 * point by point: for every eliminated l seen by a, W = H_al H_ll⁻¹ is formed once and
	 * S_ab −= W H_lb for every b ≥ a of l. Each row is written by one thread and its terms are summed in
	 * ascending l, so the result does not depend on the thread count. */
	template <int NP, int NL>
	void schur_row(int a, double lambda, double min_diag, double max_diag, double* rhs);
	/** S_ab ← H_ab (+ λD on the diagonal block), zero for blocks that only come from the elimination;
	 * rhs_a ← −g_a. */
	template <int NP>
	void start_row(int a, double lambda, double min_diag, double max_diag, double* rhs);
	/** The terms of eliminated variable l (through its H_lp block pa) on row a: rhs_a += W g_l and
	 * S_ab −= W H_lb, with W = H_al H_ll⁻¹ (na × nl) in `W`. */
	template <int NP, int NL>
	void eliminate_into_row(int a, int pa, double* W, double* rhs);
	/** δ_l = H_ll⁻¹ (−g_l − Σ H_lb δ_b). */
	template <int NP, int NL>
	void back_substitute(int l, double* delta) const;
	/** Creates the Cholesky back end for the reduced pattern (once, before the first factorisation). */
	void ensure_cholesky();

	const Program& program_;
	const NormalEquations& ne_;
	bool sparse_;
	int num_threads_;
	std::vector<double> Hll_inv_;
	// Reduced system S over kept variables.
	BlockPattern s_pattern_;
	std::vector<int> s_offset_;
	std::vector<int> s_row_begin_;  // per kept var (+1): first S block of its block row
	std::vector<int> s_pp_block_;   // per S block: the H_pp block or −1
	std::vector<double> S_;
	std::vector<const double*> s_block_ptr_;
	// Schur terms per H_lp block (a, l): the S offsets of (a, b) for the blocks (b ≥ a, l).
	std::vector<int> pl_pos_;         // per pl block: its position in elim_pl(elim)
	std::vector<int> pl_term_begin_;  // per pl block: first entry in term_s_offset_
	std::vector<int> term_s_offset_;  // per (pl block (a,l), pl block (b ≥ a, l)): S offset of (a, b)
	Eigen::VectorXd rhs_;
	std::unique_ptr<BlockCholesky> cholesky_;
};
}  // namespace swba::detail
