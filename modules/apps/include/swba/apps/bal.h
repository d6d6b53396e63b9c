/** \file bal.h
 * `swba bal`: bundle adjustment of a BAL problem (doc/bal.md) — read (swba/io/bal.h), build
 * (swba/problems/bal.h), solve with swba's LM (points eliminated by Schur), report, write the
 * requested PLY and BAL outputs. */
#pragma once

#include <swba/core/loss.h>
#include <swba/nonlinear/solver.h>

#include <iosfwd>
#include <string>

namespace swba::apps
{
/** Options of `swba bal`. */
struct BalAppOptions
{
	std::string problem_path;        ///< BAL file (required)
	std::string ply_initial;         ///< PLY of the initial values (empty: not written)
	std::string ply_final;           ///< PLY of the solution (empty: not written)
	std::string write_problem;       ///< BAL file of the solution (empty: not written)
	RobustLoss loss = RobustLoss::None;  ///< robust loss of every reprojection factor. Default none.
	double loss_scale = 1.0;         ///< loss scale a, in pixels (used by Huber and Cauchy). Default 1.
	/** The LM options (progress_to_stdout prints the per-iteration table). Defaults: SolverOptions',
	 * with num_threads 2. */
	SolverOptions solver = default_solver_options();

	static SolverOptions default_solver_options();
	/** Throws std::invalid_argument on invalid solver options or a loss that cannot be made. */
	void validate() const;
};

struct BalAppResult
{
	int num_behind_camera = 0;       ///< initial observations with the point behind the camera
	Summary summary;
};

/** Reads, solves (printing the per-iteration table if options.solver.progress_to_stdout, then the
 * full report) and writes the requested outputs. Report lines go to `out`, the "Wrote <file>" lines to `log`. Throws
 * std::invalid_argument on invalid options, std::runtime_error on unreadable input, unwritable
 * output or a failed optimisation ("optimisation failed: <the solver's message>", after the report;
 * then no solution is written). */
BalAppResult run_bal_app(const BalAppOptions& options, std::ostream& out, std::ostream& log);
}  // namespace swba::apps
