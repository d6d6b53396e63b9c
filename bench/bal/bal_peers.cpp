#include "bal_peers.h"

#include <swba/core/timing.h>
#include <swba/nonlinear/solver.h>
#include <swba/problems/bal.h>


namespace swba::bench
{
PeerResult solve_swba(const io::BalProblem& bal, const PeerSettings& s)
{
	Problem problem;
	problems::add_bal_to_problem(bal, problem);
	SolverOptions o;
	o.num_threads = s.num_threads;
	o.max_iterations = s.max_iterations;
	set_tolerances(s, o);
	o.linear_solver = s.dense ? LinearSolverType::DenseSchur : LinearSolverType::SparseSchur;
	o.stop_at_cost = s.stop_at_cost;
	const auto t0 = SteadyClock::now();
	const Summary summary = solve(problem, o);
	PeerResult r = peer_result(seconds_since(t0), summary);
	r.iterations = summary.iterations;
	r.termination = summary.message;
	for (const auto& it : summary.iterations_log) r.log.push_back({it.iteration, it.cost, it.cumulative_time_s});
	return r;
}
}  // namespace swba::bench
