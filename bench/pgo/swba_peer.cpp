// The swba peer: the stages of `swba pgo` (swba/apps/pgo.h), timed one by one.
#include <swba/apps/pgo.h>

#include "pgo_peers.h"

namespace swba::bench
{
Result run_swba(const io::PoseGraph& input, const Settings& s, RotationError model, problems::PoseGraphInit init,
				bool solve_positions)
{
	Result r;
	r.solver = "swba:" + problems::to_string(init).substr(0, 4) + (solve_positions ? "" : "-r");
	apps::PgoAppOptions o;  // as swba pgo
	o.init = init;
	o.init_solve_positions = solve_positions;
	o.rotation_error = model;
	o.solver.max_iterations = s.max_iterations;
	o.solver.num_threads = s.threads;
	o.solver.initial_trust_region_radius = s.initial_trust_region;
	for (int rep = 0; rep < s.repeat; rep++)
	{
		io::PoseGraph g = input;
		// The initialisation is timed as part of the solve (it replaces LM iterations).
		auto t0 = SteadyClock::now();
		const auto init_summary = apps::initialize_pgo(g, o);
		const double init_s = seconds_since(t0);
		const double start_cost = problems::pose_graph_cost(g, model);
		t0 = SteadyClock::now();
		auto pp = apps::build_pgo_problem(g, o);
		const double setup = seconds_since(t0);
		t0 = SteadyClock::now();
		const auto summary = apps::solve_pgo(pp, g, o);
		const double solve = init_s + seconds_since(t0);
		r.keep_fastest(rep, setup, solve, init_s);
		r.start_cost = start_cost;
		r.final_cost = problems::pose_graph_cost(g, model);
		r.reported_cost = summary.final_cost;
		r.iterations = summary.iterations;
		r.note = init_summary.brief() + "; " + summary.brief_report();
		r.solution = g;
	}
	return r;
}
}  // namespace swba::bench
