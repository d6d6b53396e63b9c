/** \file prior_only_store.h
 * (private to the smoother module) The variables only the marginal prior touches, kept out of it as
 * their Gaussian conditional given the prior's other variables, updated step by step instead of
 * re-eliminated at every solve.
 *
 * An estimator that keeps every variable it ever estimated (a SLAM map) leaves many of them connected
 * to nothing but the prior once no state of the window relates to them. Split the prior's variables into those (p, "prior-only") and
 * the others (a, "active"); in the prior's coordinates d = x ⊟ x_lin the prior is exactly
 *     p(d_a, d_p) = N(d_a; prior over a) · N(d_p; k − K d_a, C),
 * the marginal over a (what the window's solve needs, in the MarginalPrior) times the conditional of p
 * (kept here). No factor other than the prior touches p, so nothing the window does changes that
 * conditional except through a:
 *   - eliminate(): marginalising active variables M (the oldest pose) with d_M = k_M − K_M d_rest + η,
 *     η ~ N(0, C_M), gives k ← k − K_pM k_M, K ← K − K_pM K_M, C ← C + K_pM C_M K_pMᵀ (rank dim M);
 *   - absorb(): an active variable that lost its last factor but the prior leaves a, conditioned on the
 *     rest from the prior's information (H_ll⁻¹ b_l, H_ll⁻¹ H_la, H_ll⁻¹), and the prior keeps its
 *     marginal;
 *   - release(): a variable that gained a factor (e.g. observed again) goes back: the prior is
 *     multiplied by its conditional N(d_l; k_l − K_l d_a, C_ll), and the other prior-only variables are
 *     conditioned on it (C ← C − C_pl C_ll⁻¹ C_lp);
 *   - change_active(): a change of variables in the prior rewrites K's columns as it rewrites J's.
 * Each costs O(|p|² · its rank) at most, where re-eliminating p from the whole prior at every step cost
 * O(|p|³): the window's cost per step no longer grows with the cube of the prior-only dimension. The
 * split is exact (same Gaussian, rounding aside), so the estimates are those of keeping them all in the
 * prior.
 * K is kept by active variable (a block of columns each), so the prior may reorder its variables. */
#pragma once

#include "linear_conditional.h"

#include <swba/core/manifold.h>
#include <swba/nonlinear/problem.h>
#include <swba/smoother/marginal_prior.h>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <map>
#include <memory>
#include <vector>

namespace swba::smoother::detail
{
class PriorOnlyStore
{
   public:
	bool empty() const { return members_.empty(); }
	bool contains(VariableId v) const;
	/** The stored variables, in storage order. */
	std::vector<VariableId> variables() const;
	/** x_lin of a stored variable (throws std::out_of_range if absent). */
	const std::vector<double>& linearization_point(VariableId v) const;

	/** Moves `vars` (variables of the installed `prior` that no other factor touches) out of the prior:
	 * their conditional given the prior's other variables joins the store, the prior keeps the
	 * marginal of the others, and they become constant in `problem`. */
	void absorb(Problem& problem, MarginalPrior& prior, const std::vector<VariableId>& vars, double threshold);
	/** Moves `vars` (stored) back into the prior: it is multiplied by their conditional given its
	 * variables, they become variables of `problem` again at their conditional mean. */
	void release(Problem& problem, MarginalPrior& prior, const std::vector<VariableId>& vars);

	/** The elimination of active variables `marg` (tangent sizes `marg_dims`) with the conditional
	 * d_marg = k_m − K_m d_keep + η, η ~ N(0, C_m), where d_keep stacks the variables `keep` (tangent
	 * sizes `keep_dims`). */
	void eliminate(const std::vector<VariableId>& marg, const std::vector<int>& marg_dims,
				   const std::vector<VariableId>& keep, const std::vector<int>& keep_dims, const Eigen::VectorXd& k_m,
				   const Eigen::MatrixXd& K_m, const Eigen::MatrixXd& C_m);
	/** The active variable `v`'s linearisation point moves by t = x_lin_new ⊟ x_lin_old: d_v shifts. */
	void shift_active(VariableId v, const Eigen::VectorXd& t);
	/** The prior's change of variables `change` (an active variable): K's columns follow J's. */
	void change_active(const VariableChange& change);

	/** Sets every stored variable to its conditional mean x_lin ⊞ (k − K d_a) at the prior's variables'
	 * current values in `problem`. */
	void set_values(Problem& problem, const MarginalPrior& prior) const;

	/** The conditional of the stored variables `vars` given the prior's other variables (its
	 * covariance and K; prior_only_store_conditional.cpp). */
	LinearConditional conditional(const std::vector<VariableId>& vars) const;

	/** Empties the store (its variables are left as they are in the problem). */
	void clear() { *this = PriorOnlyStore(); }

   private:
	/** Index of the conditioning variable w in `prior` (throws std::logic_error if it left). */
	static int active_index(const MarginalPrior& prior, VariableId w);
	/** δ_w = x_w ⊟ x_lin,w at the problem's value and the prior's point (w at `idx` in the prior). */
	static Eigen::VectorXd active_offset(const Problem& problem, const MarginalPrior& prior, VariableId w, int idx);

	struct Member
	{
		VariableId var;
		int offset;  ///< first row in k, K, C
		int dim;
		std::vector<double> x_lin;
		std::shared_ptr<const Manifold> manifold;
	};
	/** absorb(): the prior's variables split into those joining the store (l) and the others (a). */
	struct PriorSplit
	{
		std::vector<int> lcols, acols;  ///< scalar columns of l and of a in the prior
		std::vector<VariableId> avars;
		std::vector<int> adims;
		std::vector<std::vector<double>> alin;
		std::vector<Member> joining;
	};
	static PriorSplit split_prior(const Problem& problem, const MarginalPrior& prior, const std::vector<VariableId>& vars);
	/** absorb(): the stored rows (dependence K_pl on l) conditioned on a through l's conditional `c`,
	 * and l's own rows of K. */
	void substitute_joining(const PriorSplit& sp, const Eigen::MatrixXd& K_pl, const GaussianConditional& c);
	/** absorb(): l's mean, its covariance C_ll and its cross-covariance with the stored rows. */
	void write_joining(const std::vector<Member>& joining, const Eigen::MatrixXd& K_pl, const Eigen::MatrixXd& C_ll,
					   const Eigen::VectorXd& k_l);
	/** release(): the other stored rows conditioned on the released variables (rows `lrows`, their
	 * columns C_pl of C, C_ll = L Lᵀ in `llt`, mean k_l). */
	void condition_on_released(const Problem& problem, const std::vector<VariableId>& vars, const std::vector<int>& lrows,
							   const Eigen::MatrixXd& C_pl, const Eigen::LLT<Eigen::MatrixXd>& llt,
							   const Eigen::VectorXd& k_l);
	/** release(): frees the rows of the released members. */
	void remove_members(const std::vector<VariableId>& vars);
	/** Rows of the members `vars`, in their order. */
	std::vector<int> rows_of(const std::vector<VariableId>& vars) const;
	/** Rows for a new member of `dim`: a free slot of that size, else appended (storage grows). */
	int allocate(int dim);
	/** Zeroes the rows (and columns of C) of `m` and frees them. */
	void free_rows(const Member& m);
	/** Rewrites the storage without free slots once they are half of it. */
	void compact_if_sparse();
	/** C += sign · U Uᵀ (U: the used rows), deferred: U joins the pending factors. */
	void add_update(const Eigen::MatrixXd& U, double sign);
	/** Applies the pending factors to C_'s lower triangle in one product (swba::lower_rank_update: the
	 * widest SIMD kernel this CPU runs). */
	void flush_updates();
	/** Columns `cols` of C (pending updates included), over the used rows. */
	Eigen::MatrixXd covariance_columns(const std::vector<int>& cols) const;

	/** Columns of pending factors kept before one flush. A rank-3 or rank-6 update streams all of C
	 * through memory for little arithmetic; one product of rank ~24 does the same work about twice as
	 * fast, and larger batches gain little more while each flush (one step's latency) grows with it. */
	static constexpr int kMaxPending = 24;

	// Rows [0, used_) of k, K and C are members' rows or free slots (zero); storage may be larger, so
	// that a variable joining or leaving costs no copy of C (updates are in place, O(used²) per rank).
	std::vector<Member> members_;
	std::vector<std::pair<int, int>> free_;  ///< (offset, dim) of free slots below used_
	int used_ = 0;
	Eigen::VectorXd k_;
	std::map<VariableId, Eigen::MatrixXd> K_;  ///< by active variable: storage rows, its tangent columns
	/** C = tril(C_) + P_ diag(sign_) P_ᵀ over the first pending_ columns of P_: C_ is symmetric over the
	 * storage rows with only its lower triangle kept (the covariance updates are symmetric rank updates
	 * of one triangle, half the work of general products), and the updates since the last flush wait
	 * as factors. P_'s rows of free slots and of storage beyond used_ are zero. */
	Eigen::MatrixXd C_;
	Eigen::MatrixXd P_;
	Eigen::VectorXd sign_ = Eigen::VectorXd::Zero(kMaxPending);
	int pending_ = 0;
};
}  // namespace swba::smoother::detail
