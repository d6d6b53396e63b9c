#include "bal_peers.h"

#include <swba/nonlinear/solver.h>
#include <swba/problems/bal.h>

#include <chrono>

namespace swba::bench
{
PeerResult solve_swba(const io::BalProblem& bal, const PeerSettings& s)
{
	Problem problem;
	problems::add_bal_to_problem(bal, problem);
	SolverOptions o;
	o.num_threads = s.num_threads;
	o.max_iterations = s.max_iterations;
	o.function_tolerance = s.function_tolerance;
	o.gradient_tolerance = s.gradient_tolerance;
	o.parameter_tolerance = s.parameter_tolerance;
	o.linear_solver = s.dense ? LinearSolverType::DenseSchur : LinearSolverType::SparseSchur;
	o.stop_at_cost = s.stop_at_cost;
	const auto t0 = std::chrono::steady_clock::now();
	const Summary summary = solve(problem, o);
	const auto t1 = std::chrono::steady_clock::now();
	PeerResult r;
	r.solve_time_s = std::chrono::duration<double>(t1 - t0).count();
	r.initial_cost = summary.initial_cost;
	r.final_cost = summary.final_cost;
	r.iterations = summary.iterations;
	r.termination = summary.message;
	for (const auto& it : summary.iterations_log) r.log.push_back({it.iteration, it.cost, it.cumulative_time_s});
	return r;
}
}  // namespace swba::bench
