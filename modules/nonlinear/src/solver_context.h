// Internal: what one solve() works on, built in order: the Program (ordering), its evaluator, the
// normal equations and the Schur eliminator; and the choice of the linear solver behind them
// (LinearSolverType::Auto decides which variables are eliminated and which back end factorises the
// reduced system).
#pragma once

#include <swba/nonlinear/problem.h>
#include <swba/nonlinear/solver.h>

#include "normal_equations.h"
#include "program.h"
#include "program_evaluator.h"
#include "schur_eliminator.h"

#include <set>

namespace swba::detail
{
class SolverContext
{
   public:
	/** Throws std::invalid_argument when DenseSchur/SparseSchur meet a factor between two eliminable
	 * variables (Auto keeps those in the reduced system instead). */
	SolverContext(Problem& problem, const SolverOptions& options);
	SolverContext(const SolverContext&) = delete;
	SolverContext& operator=(const SolverContext&) = delete;

	Program& program() { return program_; }
	ProgramEvaluator& evaluator() { return evaluator_; }
	NormalEquations& equations() { return equations_; }
	SchurEliminator& eliminator() { return eliminator_; }
	/** The linear solver chosen (never Auto). */
	LinearSolverType linear_solver_used() const { return used_; }

   private:
	/** Which variables are eliminated and the back end, decided before the patterns are built. */
	struct Elimination
	{
		bool use_schur = false, sparse = false;
		std::set<VariableId> keep;  ///< eliminable variables kept in the reduced system
		int reduced_dim = 0;        ///< dimension of the system to factorise (Auto only)
	};
	static Elimination choose_elimination(const Problem& problem, const SolverOptions& options);
	/** Auto: dense or sparse back end from the size and fill of the reduced system. */
	bool choose_sparse(const SolverOptions& options) const;

	Elimination elimination_;
	Program program_;
	ProgramEvaluator evaluator_;
	NormalEquations equations_;
	SchurEliminator eliminator_;
	LinearSolverType used_;
};
}  // namespace swba::detail
