// Solvers compared by the pose-graph benchmark: each solves one graph from the file's values (swba
// from its initialisation) and returns the same figures, the final cost re-evaluated with the
// reference ½ Σ rᵀΛr of problems::pose_graph_cost, so that the table compares like with like.
#pragma once

#include <swba/core/timing.h>
#include <swba/factors/relative_pose.h>
#include <swba/io/g2o.h>
#include <swba/problems/pose_graph.h>
#include <swba/problems/pose_graph_init.h>

#include <string>
#include <utility>
#include <vector>

namespace swba::bench
{
/** The benchmark's settings (command line). */
struct Settings
{
	int threads = 2;
	int max_iterations = problems::pose_graph_solver_options().max_iterations;  // as `swba pgo`
	int repeat = 1;
	int mrpt_max_iterations = 100;
	double initial_trust_region = problems::kPoseGraphInitialTrustRegion;  // swba's rows and the ceres:tr row
	bool run_ceres_tr = true;
	bool run_ceres = true;
	bool run_mrpt = true;
	std::vector<RotationError> models = {RotationError::G2o, RotationError::CeresExample};
	/** swba rows: (method, solve positions — chordal only: false = chordal rotations + odometry positions). */
	std::vector<std::pair<problems::PoseGraphInit, bool>> inits = {{problems::PoseGraphInit::Chordal, true},
																   {problems::PoseGraphInit::Odometry, true}};
	std::vector<std::string> graphs;
};

struct Result
{
	std::string solver;
	double final_cost = -1;  // pose_graph_cost of the solver's output
	double reported_cost = -1;  // what the solver itself reports (its own definition)
	int iterations = 0;
	double setup_s = 0, solve_s = 0;
	double init_s = 0;          // initialisation, included in solve_s
	double start_cost = -1;     // pose_graph_cost where the solver starts (after the initialisation)
	std::string note;
	io::PoseGraph solution;  // the solver's output (for re-evaluation under another model)

	/** Keeps the times of repetition `rep` when its solve is the fastest so far (the best of the
	 * repetitions is reported). */
	void keep_fastest(int rep, double setup, double solve, double init = 0)
	{
		if (rep > 0 && solve >= solve_s) return;
		setup_s = setup;
		solve_s = solve;
		init_s = init;
	}
};

/** swba as `swba pgo` runs it (swba/apps/pgo.h), from the initialisation `init`. */
Result run_swba(const io::PoseGraph& input, const Settings& s, RotationError model, problems::PoseGraphInit init,
				bool solve_positions);
#ifdef SWBA_BENCH_HAVE_CERES
/** Ceres with its default options, or (`initial_trust_region` > 0) with that initial radius. */
Result run_ceres(const io::PoseGraph& input, const Settings& s, RotationError model, double initial_trust_region);
#endif
#ifdef SWBA_BENCH_HAVE_MRPT_GRAPHSLAM
/** MRPT's graphslam::optimize_graph_spa_levmarq; final_cost is left for the caller (per model). */
Result run_mrpt(const io::PoseGraph& input, const Settings& s);
#endif
}  // namespace swba::bench
