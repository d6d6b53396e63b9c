// Solvers compared by the BAL benchmark: each runs one solve from a BAL problem's initial values and
// returns the same figures, so that the table compares like with like.
#pragma once

#include <swba/io/bal.h>
#include <swba/nonlinear/solver.h>

#include <string>
#include <vector>

namespace swba::bench
{
/** The settings every peer gets; the iteration cap and the tolerances default to swba's solver's
 * (Ceres's Solver::Options has the same defaults). */
struct PeerSettings
{
	int num_threads = 2;
	int max_iterations = SolverOptions{}.max_iterations;
	double function_tolerance = SolverOptions{}.function_tolerance;
	double gradient_tolerance = SolverOptions{}.gradient_tolerance;
	double parameter_tolerance = SolverOptions{}.parameter_tolerance;
	bool dense = false;        ///< DENSE_SCHUR instead of SPARSE_SCHUR
	double stop_at_cost = -1;  ///< stop once cost ≤ this (ours only; Ceres's log is used instead)
};

/** The three stopping tolerances of `s` into a solver's options (swba's SolverOptions and Ceres's
 * Solver::Options spell them alike). */
template <class Options>
void set_tolerances(const PeerSettings& s, Options& o)
{
	o.function_tolerance = s.function_tolerance;
	o.gradient_tolerance = s.gradient_tolerance;
	o.parameter_tolerance = s.parameter_tolerance;
}

struct PeerIteration
{
	int iteration = 0;
	double cost = 0;
	double cumulative_time_s = 0;
};

struct PeerResult
{
	std::string termination;
	double initial_cost = -1;
	double final_cost = -1;
	int iterations = 0;        ///< LM iterations (accepted + rejected), without Ceres's iteration 0
	double solve_time_s = 0;   ///< wall time of the solve call (problem already built)
	std::vector<PeerIteration> log;
};

/** The time and the costs of a solve (swba's Summary and Ceres's Solver::Summary spell the costs alike). */
template <class Summary>
PeerResult peer_result(double solve_time_s, const Summary& summary)
{
	PeerResult r;
	r.solve_time_s = solve_time_s;
	r.initial_cost = summary.initial_cost;
	r.final_cost = summary.final_cost;
	return r;
}

PeerResult solve_swba(const io::BalProblem& bal, const PeerSettings& s);
#ifdef SWBA_HAVE_CERES
PeerResult solve_ceres(const io::BalProblem& bal, const PeerSettings& s);
#endif
}  // namespace swba::bench
