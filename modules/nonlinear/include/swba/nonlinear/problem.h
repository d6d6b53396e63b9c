/** \file problem.h
 * A nonlinear least-squares problem: variables (values on manifolds) and factors connecting them
 * (Ceres's Problem with GTSAM-style factors). The problem owns the values.
 *
 * Variables belong to a group: `Group::Kept` (poses, cameras) or `Group::Eliminable` (landmarks,
 * points). The solver orders kept variables first and eliminates the eliminable group by a Schur
 * complement; an eliminable variable that shares a factor with another one cannot be eliminated on
 * its own: LinearSolverType::Auto keeps it in the reduced system, the explicit Schur types throw.
 * Constant variables are removed from the ordering entirely. */
#pragma once

#include <swba/core/factor.h>
#include <swba/core/loss.h>
#include <swba/core/manifold.h>

#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <memory>
#include <set>
#include <vector>

namespace swba
{
using VariableId = std::int64_t;
using FactorId = std::int64_t;

enum class Group
{
	Kept,
	Eliminable
};

class Problem
{
   public:
	struct Variable
	{
		std::vector<double> value;
		std::shared_ptr<const Manifold> manifold;
		Group group = Group::Kept;
		bool constant = false;
		std::set<FactorId> factors;
	};
	struct FactorEntry
	{
		std::shared_ptr<const Factor> factor;
		std::vector<VariableId> variables;
		std::shared_ptr<const LossFunction> loss;  // null = plain least squares
	};

	/** Adds a variable with initial value `x0` (ambient_size doubles). O(log n). */
	VariableId add_variable(const double* x0, std::shared_ptr<const Manifold> manifold,
							Group group = Group::Kept);
	VariableId add_variable(const Eigen::VectorXd& x0, std::shared_ptr<const Manifold> manifold,
							Group group = Group::Kept)
	{
		return add_variable(x0.data(), std::move(manifold), group);
	}
	/** Adds an SE(3) pose variable (SE3Manifold). */
	VariableId add_pose(const mrpt::poses::CPose3D& pose, Group group = Group::Kept);

	/** Adds a factor; throws std::invalid_argument on unknown variables, a repeated variable, or
	 * tangent sizes that do not match the factor's. */
	FactorId add_factor(std::shared_ptr<const Factor> factor, std::vector<VariableId> variables,
						std::shared_ptr<const LossFunction> loss = nullptr);

	/** Removes a factor (throws std::out_of_range if unknown). */
	void remove_factor(FactorId id);
	/** Removes a variable and every factor connected to it. */
	void remove_variable(VariableId id);

	void set_constant(VariableId id, bool constant = true) { var(id).constant = constant; }
	bool is_constant(VariableId id) const { return var(id).constant; }
	bool has_variable(VariableId id) const { return variables_.count(id) > 0; }
	bool has_factor(FactorId id) const { return factors_.count(id) > 0; }

	double* value(VariableId id) { return var(id).value.data(); }
	const double* value(VariableId id) const { return var(id).value.data(); }
	/** Value of an SE(3) variable as a CPose3D. */
	mrpt::poses::CPose3D pose(VariableId id) const;
	void set_pose(VariableId id, const mrpt::poses::CPose3D& pose);
	void set_value(VariableId id, const double* x);

	const Variable& variable(VariableId id) const { return var(id); }
	const FactorEntry& factor(FactorId id) const;
	const std::map<VariableId, Variable>& variables() const { return variables_; }
	const std::map<FactorId, FactorEntry>& factors() const { return factors_; }
	size_t num_variables() const { return variables_.size(); }
	size_t num_factors() const { return factors_.size(); }

	/** Total cost ½Σρ(‖W r‖²) at the current values (dropped factors count as zero).
	 * If `num_dropped` is given, it receives how many factors could not be evaluated. */
	double cost(int* num_dropped = nullptr) const;

   private:
	Variable& var(VariableId id);
	const Variable& var(VariableId id) const;

	std::map<VariableId, Variable> variables_;
	std::map<FactorId, FactorEntry> factors_;
	VariableId next_variable_ = 0;
	FactorId next_factor_ = 0;
};
}  // namespace swba
