/** \file marginal_prior.h
 * The marginal prior of a fixed-lag smoother: what is left of the marginalised states, kept as the
 * linearised residual r = e + J (x ⊟ x_lin) over the variables they were connected to (VINS-Mono /
 * basalt style; in the problem as one LinearPriorFactor), together with its information H = JᵀJ,
 * b = −Jᵀe (the Schur complement it came from) while that is known, so that the next marginalisation
 * and the prior-only elimination need not form JᵀJ over the whole prior again. */
#pragma once

#include <swba/linear/marginal.h>
#include <swba/nonlinear/problem.h>

#include <Eigen/Core>
#include <functional>
#include <utility>
#include <vector>

namespace swba::smoother
{
/** A first-order change of variables in the prior: the prior variable `old_var` is replaced by
 * `new_var`, the two related around the linearisation points by
 *     d_old ≈ D (H_new d_new + Σ H_i d_yi),
 * with d = x ⊟ x_lin and the variables y_i already in the prior. Block sizes are the variables'
 * tangent sizes (D: old × m, H_new: m × new, H_i: m × y_i, for any inner size m): the model gives its
 * Jacobians as it produces them, e.g. D = ∂φ/∂h and ∂h/∂x for x_old = φ(h(x_new, y_1, …)).
 * change_columns() applies it to a block of columns; every container of columns over the prior's
 * variables (the prior's J, the linear tail's K, the prior-only store's K) goes through it. */
struct VariableChange
{
	VariableId old_var = -1;
	VariableId new_var = -1;
	std::vector<double> new_x_lin;        ///< x_new at the prior's linearisation point
	std::vector<double> first_estimate;   ///< x_new where the Jacobians were evaluated (its first estimate)
	Eigen::MatrixXd D;
	Eigen::MatrixXd H_new;
	/** (y_i, H_i); containers update their columns in this order. */
	std::vector<std::pair<VariableId, Eigen::MatrixXd>> H_others;
};

/** The columns that replace M_old, a linear map's block on d_old, under `change`: M_old d_old =
 * (M_old D H_new) d_new + Σ (M_old D H_i) d_yi. Returns {new_var, M_old D H_new} followed by each
 * {y_i, M_old D H_i} (to be added to y_i's columns, which are zero where absent). Throws
 * std::invalid_argument when the sizes disagree. */
std::vector<std::pair<VariableId, Eigen::MatrixXd>> change_columns(const VariableChange& change,
																   const Eigen::MatrixXd& M_old);

class MarginalPrior
{
   public:
	/** True while the prior's factor is in the problem (a non-empty prior outside a solve). */
	bool installed() const { return factor_ >= 0; }
	FactorId factor() const { return factor_; }
	const std::vector<VariableId>& variables() const { return vars_; }
	const Eigen::MatrixXd& J() const { return J_; }
	const Eigen::VectorXd& e() const { return e_; }
	/** Ambient value of each variable at which the prior was linearised. */
	const std::vector<std::vector<double>>& linearization_points() const { return x_lin_; }
	/** Whether H() and b() hold JᵀJ and −Jᵀe (true from a marginalisation on). */
	bool has_information() const { return has_information_; }
	const Eigen::MatrixXd& H() const { return H_; }
	const Eigen::VectorXd& b() const { return b_; }
	/** Rows of J (0: no prior). */
	int rank() const { return static_cast<int>(J_.rows()); }

	/** The prior's variables split in two by a predicate: their positions in variables() and their
	 * scalar columns in J, each part in the prior's order. */
	struct Partition
	{
		std::vector<std::size_t> first, second;
		std::vector<int> first_columns, second_columns;
	};
	/** Splits the variables by `in_first` (tangent sizes from `problem`). Throws std::invalid_argument
	 * when their sizes and J's columns disagree. */
	Partition partition(const Problem& problem, const std::function<bool(VariableId)>& in_first) const;
	/** Position of `v` in variables(), −1 if it is not in the prior. O(variables). */
	int index_of(VariableId v) const;
	/** First column of variable `index` in J (tangent sizes from the problem). */
	int column_of(const Problem& problem, int index) const;

	/** Replaces the prior by the marginal `m` over `vars` and installs its factor; the previous factor,
	 * if still installed, is removed. `m` is a quadratic in the offsets from the variables' current
	 * values in the problem; it is stored around `x_lin` (one ambient value per variable; empty: the
	 * current values), i.e. re-expressed to first order in x ⊟ x_lin: e − J s, b + H s with
	 * s = x_current ⊟ x_lin. A smoother with first-estimate Jacobians passes the first estimates, so
	 * the prior's point, its Jacobian and every factor's Jacobian agree (the prior's residual is then
	 * invariant, to first order, under the motions its Jacobian is blind to). A zero-rank `m` leaves the
	 * prior empty. Throws std::invalid_argument when the sizes disagree. */
	void reset(Problem& problem, std::vector<VariableId> vars, MarginalizationResult m,
			   std::vector<std::vector<double>> x_lin = {});
	/** reset() for an `m` that is already a quadratic in d = x ⊟ x_lin (no shift; one x_lin per
	 * variable). */
	void assign(Problem& problem, std::vector<VariableId> vars, MarginalizationResult m,
				std::vector<std::vector<double>> x_lin);
	/** Multiplies the prior by the linear factor ½‖e_rows + J_rows d‖² whose columns are the prior's
	 * variables followed by `new_vars` (appended with linearisation points `new_x_lin`): J and e gain
	 * rows, H and b (known) the factor's information. Re-installs the factor. Throws
	 * std::invalid_argument when the sizes disagree. */
	void append_rows(Problem& problem, const std::vector<VariableId>& new_vars,
					 const std::vector<std::vector<double>>& new_x_lin, const Eigen::MatrixXd& J_rows,
					 const Eigen::VectorXd& e_rows);
	/** Empties the prior; its factor, if any, must already be gone from the problem. */
	void clear();
	/** Removes the prior's factor from the problem (the prior itself is kept). */
	void uninstall(Problem& problem);
	/** (Re)builds the prior's factor from J, e, x_lin and adds it to the problem, removing the old one if
	 * installed; an empty prior (no variables or rank 0) is cleared instead. */
	void install(Problem& problem);
	/** Marks the factor as removed by the caller (it was among the factors of a marginalisation). */
	void forget_factor() { factor_ = -1; }

	/** Adds `v` with zero columns (x_lin = its current value) if absent; returns its index. H and b
	 * (when known) are extended with zeros: the new columns of J are zero. */
	int add_variable(const Problem& problem, VariableId v);
	/** The change of variables (see VariableChange) in the prior: rewrites J's columns through
	 * change_columns(), refreshes the same rows/columns of H and entries of b, and replaces old_var by new_var with x_lin = new_x_lin.
	 * Does not touch the problem: call install() afterwards. */
	void change_variable(const Problem& problem, const VariableChange& change);

   private:
	/** After J's columns [c0, c0 + n) were rewritten: recomputes the same rows/columns of H = JᵀJ and
	 * entries of b = −Jᵀe (O(rank·cols·n), not a new JᵀJ). */
	void refresh_information(int c0, int n);

	FactorId factor_ = -1;
	std::vector<VariableId> vars_;
	Eigen::MatrixXd J_;
	Eigen::VectorXd e_;
	std::vector<std::vector<double>> x_lin_;
	Eigen::MatrixXd H_;
	Eigen::VectorXd b_;
	bool has_information_ = false;
};
}  // namespace swba::smoother
