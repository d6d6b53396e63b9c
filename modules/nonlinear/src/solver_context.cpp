#include "solver_context.h"

#include <algorithm>

namespace swba::detail
{
namespace
{
/** Auto: reduced systems up to this dimension are always factorised densely. */
constexpr int kAutoDenseAlwaysDim = 200;
/** Auto: between that and dense_max_dim, dense only with at least this upper-block fill. */
constexpr double kAutoDenseMinFill = 0.25;

/** Schur elimination pays when eliminated variables have few observations each (BAL: ~4 per point);
 * with long feature tracks (SLAM: hundreds of poses per landmark) the reduced system fills in
 * (Σ n_l² blocks) and the full sparse normal equations are cheaper. Variables in `linked` stay kept. */
bool short_tracks(const Problem& problem, const std::set<VariableId>& linked)
{
	double terms = 0, blocks = 0;
	for (const auto& [id, v] : problem.variables())
	{
		if (v.constant || v.group != Group::Eliminable || linked.count(id)) continue;
		const double n = static_cast<double>(v.factors.size());
		terms += n * (n + 1) / 2;
		blocks += n;
	}
	return terms <= 8.0 * std::max(1.0, blocks);
}

LinearSolverType linear_solver_type(bool use_schur, bool sparse)
{
	return use_schur ? (sparse ? LinearSolverType::SparseSchur : LinearSolverType::DenseSchur)
					 : (sparse ? LinearSolverType::SparseNormal : LinearSolverType::DenseNormal);
}
}  // namespace

SolverContext::Elimination SolverContext::choose_elimination(const Problem& problem, const SolverOptions& options)
{
	Elimination e;
	switch (options.linear_solver)
	{
		case LinearSolverType::DenseSchur: e.use_schur = true; break;
		case LinearSolverType::SparseSchur: e.use_schur = e.sparse = true; break;
		case LinearSolverType::DenseNormal: break;
		case LinearSolverType::SparseNormal: e.sparse = true; break;
		case LinearSolverType::Auto: break;
	}
	if (options.linear_solver != LinearSolverType::Auto) return e;
	// Eliminable variables linked to each other by a factor (a marginalisation prior over landmarks)
	// stay in the reduced system; the others are eliminated when that pays: with short tracks, or
	// whenever the full system would be factorised densely anyway (eliminating a variable seen by n
	// kept blocks costs O((n·t)²) flops, never more than carrying its rows through the dense LLT).
	e.keep = linked_eliminable_variables(problem);
	int full_dim = 0, reduced_dim = 0;
	bool has_elim = false;
	for (const auto& [id, v] : problem.variables())
	{
		if (v.constant) continue;
		const int t = v.manifold->tangent_size();
		full_dim += t;
		if (v.group == Group::Eliminable && e.keep.count(id) == 0)
			has_elim = true;
		else
			reduced_dim += t;
	}
	e.use_schur = has_elim && (full_dim <= options.dense_max_dim || short_tracks(problem, e.keep));
	e.reduced_dim = e.use_schur ? reduced_dim : full_dim;
	e.sparse = e.reduced_dim > options.dense_max_dim;
	return e;
}

bool SolverContext::choose_sparse(const SolverOptions& options) const
{
	// Dense only pays when the reduced system is small or mostly filled: a pose graph of 744
	// unknowns with ~5 % block fill factorises ~8× faster with CHOLMOD than with a dense LLT.
	const int dim = elimination_.reduced_dim;
	return !(dim <= kAutoDenseAlwaysDim ||
			 (dim <= options.dense_max_dim && eliminator_.reduced_block_fill() >= kAutoDenseMinFill));
}

SolverContext::SolverContext(Problem& problem, const SolverOptions& options)
	: elimination_(choose_elimination(problem, options)),
	  program_(problem, elimination_.use_schur, elimination_.keep),
	  evaluator_(program_, options.num_threads),
	  equations_(program_, evaluator_, options.num_threads),
	  eliminator_(program_, equations_, elimination_.sparse, options.num_threads),
	  used_(options.linear_solver)
{
	if (options.linear_solver != LinearSolverType::Auto) return;
	eliminator_.set_sparse(choose_sparse(options));
	used_ = linear_solver_type(elimination_.use_schur, eliminator_.sparse());
}
}  // namespace swba::detail
