// Internal: the block structure of a Program's normal equations H δ = −g (H = JᵀJ, g = Jᵀr) and their
// assembly from the evaluated Jacobians: kept-kept blocks H_pp (upper triangle), eliminated-kept
// blocks H_lp, eliminated diagonal blocks H_ll, and the gradient g over [kept; eliminated].
#pragma once

#include "program.h"
#include "program_evaluator.h"

#include <Eigen/Core>
#include <utility>
#include <vector>

namespace swba::detail
{
/** One factor's contribution to a block (a, b) of H: Jᵀ_{slot_a} J_{slot_b}. `cache` ≥ 0 for a factor
 * whose whitened Jacobian is constant (Factor::constant_jacobian, no loss): the product's offset in the
 * cache, formed at the first assembly of the solve and added from there afterwards. */
struct Contribution
{
	int factor, slot_a, slot_b;
	int cache = -1;
};

/** An eliminated-kept block, stored as H_lp = H_plᵀ (elim rows × kept columns, row-major) so that the
 * Schur update reads contiguous rows. */
struct PlBlock
{
	int kept, elim, offset;
	std::vector<Contribution> contrib;  // slot_a kept slot, slot_b elim slot
};

class NormalEquations
{
   public:
	/** Builds the block patterns of `program` (deterministic order: H_pp blocks by (i, j), H_lp blocks
	 * by (elim, kept)). Every kept variable has its diagonal block. */
	NormalEquations(const Program& program, const ProgramEvaluator& evaluator, int num_threads);

	/** Assembles H (blocks) and g from the evaluator's last Jacobian evaluation; factors it could not
	 * evaluate are left out. */
	void assemble();
	/** max |g_i|. */
	double gradient_max_norm() const;
	/** Predicted decrease of the linear model for step δ over [kept; eliminated]: −gᵀδ − ½ δᵀHδ. */
	double model_decrease(const Eigen::VectorXd& delta) const;
	/** Factor f's share of it: −r_fᵀJ_fδ − ½‖J_fδ‖² from the last linearisation (0 for a factor that
	 * was not evaluable there). Summed over all factors it is model_decrease(δ). */
	double factor_model_decrease(int f, const Eigen::VectorXd& delta) const;

	/** @name The blocks, for the elimination.
	 * @{ */
	const std::vector<std::pair<int, int>>& pp_blocks() const { return pp_blocks_; }
	const double* hpp(int b) const { return Hpp_.data() + pp_offset_[b]; }
	const std::vector<PlBlock>& pl_blocks() const { return pl_blocks_; }
	const double* hlp(int b) const { return Hlp_.data() + pl_blocks_[b].offset; }
	/** The H_lp blocks of eliminated variable l (ascending kept) / of kept variable a (ascending elim). */
	const std::vector<int>& elim_pl(int l) const { return elim_pl_[l]; }
	const std::vector<int>& kept_pl(int a) const { return kept_pl_[a]; }
	/** H_ll of eliminated variable l, at offset ll_offset(l) of the H_ll storage (Σ_l t_l² doubles). */
	const double* hll(int l) const { return Hll_.data() + ll_offset_[l]; }
	int ll_offset(int l) const { return ll_offset_[l]; }
	/** g over [kept; eliminated]. */
	const double* gradient() const { return g_.data(); }
	/** @} */

   private:
	void collect_blocks();
	void sort_pp_blocks();
	void lay_out_storage();

	/** Gives every contribution of a constant-Jacobian factor its cache offset. */
	void lay_out_cache();
	/** H (na × nb) += contribution c, from its cache when it has one. */
	void add_contribution(const Contribution& c, int na, int nb, bool transpose_slots, double* H);

	void assemble_pp(int b);
	void assemble_pl(int b);
	void assemble_ll(int l);
	void assemble_kept_gradient(int a);

	const Program& program_;
	const ProgramEvaluator& evaluator_;
	int num_threads_;
	// Kept-kept blocks H_pp (upper, i ≤ j), with contributions.
	std::vector<std::pair<int, int>> pp_blocks_;
	std::vector<int> pp_offset_;
	std::vector<std::vector<Contribution>> pp_contrib_;
	std::vector<double> Hpp_;
	std::vector<PlBlock> pl_blocks_;
	std::vector<std::vector<int>> elim_pl_;  // per elim var: its pl blocks (ascending kept)
	std::vector<std::vector<int>> kept_pl_;  // per kept var: its pl blocks (ascending elim)
	std::vector<double> Hlp_;
	std::vector<int> ll_offset_;
	std::vector<double> Hll_;
	std::vector<double> g_;  // [kept; elim]
	std::vector<double> cache_;       // Jᵀ J products of constant-Jacobian factors
	std::vector<char> cache_ready_;   // per cached contribution, at its cache offset
};
}  // namespace swba::detail
