// Internal: the block structure of a Problem's normal equations, their assembly from evaluated
// Jacobians, and the damped solve with Schur elimination of the eliminable variables.
#pragma once

#include <swba/linear/block_cholesky.h>
#include <swba/nonlinear/problem.h>
#include <swba/nonlinear/solver.h>

#include <memory>
#include <set>
#include <vector>

namespace swba::detail
{
/** A non-constant variable in the ordering. */
struct OrderedVariable
{
	VariableId id;
	Problem::Variable* var;
	int tangent;
	int offset;  ///< scalar offset in the kept vector (kept) or the eliminated vector (eliminated)
};

/** One factor's evaluation storage. */
struct FactorSlotInfo
{
	const Factor* factor;
	const LossFunction* loss;
	int m;
	int residual_offset;
	std::vector<double*> values;        ///< per factor variable
	std::vector<int> kind;              ///< 0 kept, 1 eliminated, 2 constant
	std::vector<int> index;             ///< index into kept/elim lists (−1 if constant)
	std::vector<int> jacobian_offset;   ///< into the Jacobian buffer (−1 if constant)
};

struct Contribution
{
	int factor, slot_a, slot_b;
};

/** The non-constant eliminable variables that share a factor with another non-constant eliminable
 * variable (e.g. landmarks linked by a marginalisation prior). Their block of H is not block diagonal,
 * so they cannot be eliminated one by one; every other eliminable variable still can (Ceres asks the
 * user for such an independent set; here it is the eliminable group minus these). */
std::set<VariableId> linked_eliminable_variables(const Problem& problem);

class NormalEquations
{
   public:
	/** Builds the ordering (kept first, then eliminated; constants removed) and all block patterns.
	 * `use_schur` false puts every non-constant variable in the kept group. `keep` (only with
	 * `use_schur`): eliminable variables kept instead of eliminated, normally
	 * linked_eliminable_variables(); a factor that still links two eliminated variables throws
	 * std::invalid_argument. */
	NormalEquations(Problem& problem, bool use_schur, bool sparse, int num_threads,
					const std::set<VariableId>& keep = {});

	int kept_dim() const { return kept_dim_; }
	int elim_dim() const { return elim_dim_; }
	int num_kept() const { return static_cast<int>(kept_.size()); }
	int num_elim() const { return static_cast<int>(elim_.size()); }
	int num_constant() const { return num_constant_; }
	bool sparse() const { return sparse_; }
	/** Chooses the back end for the reduced system (only before the first solve_damped). */
	void set_sparse(bool sparse);
	/** Fraction of the upper block triangle of the reduced system that is structurally non-zero. */
	double reduced_block_fill() const;
	int num_factors() const { return static_cast<int>(factors_.size()); }

	/** Evaluates every factor at the current values; with `jacobians` also the Jacobians.
	 * Returns the total cost; `dropped` receives the count of unevaluable factors and
	 * `newly_dropped` (optional) those that were evaluable at the previous evaluation but are not now. */
	double evaluate(bool jacobians, int* dropped, int* newly_dropped = nullptr);
	/** Assembles H = JᵀJ (blocks) and g = Jᵀr from the last Jacobian evaluation. */
	void assemble();
	/** max |g_i|. */
	double gradient_max_norm() const;
	/** Solves (H + λ D) δ = −g, D = clamp(diag H); δ over [kept; eliminated]. False if not SPD. */
	bool solve_damped(double lambda, double min_diag, double max_diag, Eigen::VectorXd& delta);
	/** Predicted decrease of the linear model for step δ: −gᵀδ − ½ δᵀHδ. */
	double model_decrease(const Eigen::VectorXd& delta) const;

	/** Backs up / restores the values of all non-constant variables. */
	void save_values();
	void restore_values();
	/** x ← x ⊞ δ for all non-constant variables. */
	void apply_step(const Eigen::VectorXd& delta);
	double values_norm() const;

   private:
	void build_patterns();

	/** Damped inverse H_ll⁻¹ of one eliminated variable; false (and a zero inverse) if not SPD. */
	template <int NL>
	bool invert_damped_ll(int l, double lambda, double min_diag, double max_diag);
	/** Block row a of the reduced system S (blocks (a, b ≥ a)) and its right-hand side, streamed
	 * point by point: for every eliminated l seen by a, W = H_al H_ll⁻¹ is formed once and
	 * S_ab −= W H_lb for every b ≥ a of l. Each row is written by one thread and its terms are summed in
	 * ascending l, so the result does not depend on the thread count. */
	template <int NP, int NL>
	void schur_row(int a, double lambda, double min_diag, double max_diag, double* rhs);
	/** δ_l = H_ll⁻¹ (−g_l − Σ H_lb δ_b). */
	template <int NP, int NL>
	void back_substitute(int l, double* delta) const;
	/** Creates the Cholesky back end for the reduced pattern (once, before the first factorisation). */
	void ensure_cholesky();

	Problem& problem_;
	bool use_schur_, sparse_;
	int num_threads_;
	std::vector<OrderedVariable> kept_, elim_;
	int kept_dim_ = 0, elim_dim_ = 0, num_constant_ = 0;
	int uniform_kept_ = 0, uniform_elim_ = 0;  // common tangent size of all kept / eliminated (0: mixed)
	std::vector<FactorSlotInfo> factors_;
	std::vector<double> residuals_, jacobians_;
	std::vector<char> valid_, valid_before_;
	std::vector<double> factor_cost_;
	std::vector<std::vector<std::pair<int, int>>> var_factors_kept_, var_factors_elim_;  // (factor, slot)

	// Kept-kept blocks H_pp (upper, i ≤ j), with contributions.
	std::vector<std::pair<int, int>> pp_blocks_;
	std::vector<int> pp_offset_;
	std::vector<std::vector<Contribution>> pp_contrib_;
	std::vector<double> Hpp_;
	std::vector<int> pp_diag_block_;  // per kept var: its diagonal block index
	// Eliminated-kept blocks, stored as H_lp = H_plᵀ (elim rows × kept columns, row-major) so that
	// the Schur update reads contiguous rows.
	struct PlBlock
	{
		int kept, elim, offset;
		std::vector<Contribution> contrib;  // slot_a kept slot, slot_b elim slot
	};
	std::vector<PlBlock> pl_blocks_;
	std::vector<std::vector<int>> elim_pl_;  // per elim var: its pl blocks (ascending kept)
	std::vector<std::vector<int>> kept_pl_;  // per kept var: its pl blocks (ascending elim)
	std::vector<int> pl_pos_;                // per pl block: its position in elim_pl_[elim]
	std::vector<int> pl_term_begin_;         // per pl block: first entry in term_s_offset_
	std::vector<int> term_s_offset_;         // per (pl block (a,l), pl block (b ≥ a, l)): S offset of (a, b)
	std::vector<double> Hlp_;
	std::vector<int> ll_offset_;
	std::vector<double> Hll_, Hll_inv_;
	std::vector<double> g_;  // [kept; elim]
	// Reduced system S over kept variables.
	BlockPattern s_pattern_;
	std::vector<int> s_offset_;
	std::vector<int> s_row_begin_;  // per kept var (+1): first S block of its block row
	std::vector<int> s_pp_block_;   // per S block: the H_pp block or −1
	std::vector<double> S_;
	std::vector<const double*> s_block_ptr_;
	Eigen::VectorXd rhs_;
	std::unique_ptr<BlockCholesky> cholesky_;
	std::vector<double> backup_;
};
}  // namespace swba::detail
