/** \file pgo.h
 * `swba pgo`: pose-graph optimisation of a g2o file (doc/pgo.md) — read (swba/io/g2o.h), initial
 * values (swba/problems/pose_graph_init.h), problem with its gauge (swba/problems/pose_graph.h),
 * LM, the optimised graph written back. The stages are also callable one by one on a graph in memory
 * (initialize_pgo, build_pgo_problem, solve_pgo), for benchmarks that time them. */
#pragma once

#include <swba/core/loss.h>
#include <swba/io/g2o.h>
#include <swba/nonlinear/solver.h>
#include <swba/problems/pose_graph.h>
#include <swba/problems/pose_graph_init.h>

#include <iosfwd>
#include <string>

namespace swba::apps
{
/** Options of `swba pgo`; every field documents its default. */
struct PgoAppOptions
{
	std::string input_path;   ///< g2o file (required by run_pgo_app)
	std::string output_path;  ///< optimised graph (empty: not written)
	/** How the g2o file is read (swba/io/g2o.h). read.information, for edge informations that are not
	 * positive definite: Strict = an error (default), Repair = replaced by the nearest positive-definite
	 * matrix, counted on `log` and in the report. */
	io::G2oReadOptions read;
	/** Initial values. Default chordal rotations, then positions by linear least squares. */
	problems::PoseGraphInit init = problems::PoseGraphInit::Chordal;
	/** Chordal only: false = chordal rotations, positions composed along the odometry tree. Default true. */
	bool init_solve_positions = true;
	/** Gauge. Default Fixed (FIX lines, else the lowest-id vertex constant). */
	problems::PoseGraphGauge gauge = problems::PoseGraphGauge::Fixed;
	/** σ of the gauge prior (gauge Prior), m and rad. Default 1e-3. */
	double prior_sigma = 1e-3;
	/** Robust loss of every edge, scale in whitened residual units. Default none, scale 1. */
	RobustLoss loss = RobustLoss::None;
	double loss_scale = 1.0;
	/** Rotation error of 3D edges (factors/relative_pose.h). Default G2o. */
	RotationError rotation_error = RotationError::G2o;
	/** LM options. Default problems::pose_graph_solver_options(). */
	SolverOptions solver = problems::pose_graph_solver_options();

	/** Throws std::invalid_argument on invalid values: prior_sigma ≤ 0, a loss that cannot be
	 * made, a Schur linear solver (a pose graph has no variables to eliminate), invalid LM options. */
	void validate() const;
	problems::PoseGraphInitOptions init_options() const;
	problems::PoseGraphProblemOptions problem_options() const;
};

struct PgoAppResult
{
	problems::PoseGraphInitSummary init;
	Summary summary;
	int num_constant = 0;     ///< vertices held constant
	bool has_prior = false;   ///< a gauge prior on the first vertex
	int repaired_information = 0;  ///< edge informations replaced (InformationPolicy::Repair)
};

/** Stage 1: overwrites the graph's non-anchor vertex values with the initial values of options.init. */
problems::PoseGraphInitSummary initialize_pgo(io::PoseGraph& graph, const PgoAppOptions& options);
/** Stage 2: the problem with the options' gauge, loss and rotation error. */
problems::PoseGraphProblem build_pgo_problem(const io::PoseGraph& graph, const PgoAppOptions& options);
/** Stage 3: LM on the problem (options.solver), the solution copied back into the graph. */
Summary solve_pgo(problems::PoseGraphProblem& problem, io::PoseGraph& graph, const PgoAppOptions& options);

/** The whole `swba pgo`: reads options.input_path, runs the three stages, prints the report to `out`
 * (warnings about skipped lines and, with InformationPolicy::Repair, the line "repaired N of M edge
 * information matrices (…)" to `log`) and writes options.output_path. Throws
 * std::invalid_argument on invalid options, std::runtime_error on unreadable input (a graph without
 * vertices included), initial values that are not finite (initialize_pose_graph), unwritable output or a
 * failed optimisation (after the report: a solver failure, or a vertex not finite at the solution; then
 * nothing is written). */
PgoAppResult run_pgo_app(const PgoAppOptions& options, std::ostream& out, std::ostream& log);
}  // namespace swba::apps
