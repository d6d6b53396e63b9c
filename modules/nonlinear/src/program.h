// Internal: a Problem laid out for one solve (Ceres's Program): the non-constant variables in solver
// order (kept first, then eliminated; constants removed), each factor's slots in the residual and
// Jacobian buffers, and the operations on the ordered values (x ⊞ δ, backup, norm).
#pragma once

#include <swba/nonlinear/problem.h>

#include <Eigen/Core>
#include <map>
#include <set>
#include <utility>
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

/** Where a factor's variable sits in the ordering (FactorSlotInfo::kind). */
constexpr int kKeptSlot = 0, kEliminatedSlot = 1, kConstantSlot = 2;

/** One factor's evaluation storage. */
struct FactorSlotInfo
{
	const Factor* factor;
	const LossFunction* loss;
	int m;
	int residual_offset;
	std::vector<double*> values;        ///< per factor variable
	std::vector<int> kind;              ///< kKeptSlot, kEliminatedSlot or kConstantSlot
	std::vector<int> index;             ///< index into kept/elim lists (−1 if constant)
	std::vector<int> jacobian_offset;   ///< into the Jacobian buffer (−1 if constant)
};

/** (factor index, slot) of a factor on a variable. */
using FactorSlot = std::pair<int, int>;

/** The non-constant eliminable variables that share a factor with another non-constant eliminable
 * variable (e.g. landmarks linked by a marginalisation prior). Their block of H is not block diagonal,
 * so they cannot be eliminated one by one; every other eliminable variable still can (Ceres asks the
 * user for such an independent set; here it is the eliminable group minus these). */
std::set<VariableId> linked_eliminable_variables(const Problem& problem);

class Program
{
   public:
	/** Orders kept variables first (by id), then eliminated ones (by id); constants are removed.
	 * `use_schur` false puts every non-constant variable in the kept group. `keep` (only with
	 * `use_schur`): eliminable variables kept instead of eliminated, normally
	 * linked_eliminable_variables(); a factor that still links two eliminated variables throws
	 * std::invalid_argument. */
	Program(Problem& problem, bool use_schur, const std::set<VariableId>& keep = {});

	const Problem& problem() const { return problem_; }
	const std::vector<OrderedVariable>& kept() const { return kept_; }
	const std::vector<OrderedVariable>& elim() const { return elim_; }
	int kept_dim() const { return kept_dim_; }
	int elim_dim() const { return elim_dim_; }
	int num_kept() const { return static_cast<int>(kept_.size()); }
	int num_elim() const { return static_cast<int>(elim_.size()); }
	int num_constant() const { return num_constant_; }
	/** Common tangent size of all kept / all eliminated variables (0: mixed or none). */
	int uniform_kept_tangent() const { return uniform_kept_; }
	int uniform_elim_tangent() const { return uniform_elim_; }

	int num_factors() const { return static_cast<int>(factors_.size()); }
	const FactorSlotInfo& factor(int f) const { return factors_[f]; }
	/** Scalar sizes of the stacked residuals and of the Jacobian blocks of non-constant variables. */
	int residual_size() const { return residual_size_; }
	int jacobian_size() const { return jacobian_size_; }
	/** The factors on kept variable a / eliminated variable l, in factor order. */
	const std::vector<FactorSlot>& kept_factors(int a) const { return var_factors_kept_[a]; }
	const std::vector<FactorSlot>& elim_factors(int l) const { return var_factors_elim_[l]; }

	/** Backs up / restores the values of all non-constant variables. */
	void save_values();
	void restore_values();
	/** x ← x ⊞ δ for all non-constant variables; δ over [kept; eliminated]. */
	void apply_step(const Eigen::VectorXd& delta);
	double values_norm() const;

   private:
	using Placement = std::map<VariableId, std::pair<int, int>>;  // id -> (kind, index)
	Placement order_variables(bool use_schur, const std::set<VariableId>& keep);
	void add_factor(FactorId id, const Problem::FactorEntry& entry, const Placement& where);

	Problem& problem_;
	std::vector<OrderedVariable> kept_, elim_;
	int kept_dim_ = 0, elim_dim_ = 0, num_constant_ = 0;
	int uniform_kept_ = 0, uniform_elim_ = 0;
	std::vector<FactorSlotInfo> factors_;
	int residual_size_ = 0, jacobian_size_ = 0;
	std::vector<std::vector<FactorSlot>> var_factors_kept_, var_factors_elim_;
	std::vector<double> backup_;
};
}  // namespace swba::detail
