/** \file pose_graph.h
 * A pose graph (swba/io/g2o.h) as a swba::Problem: one variable per vertex (SE3Manifold, or
 * (x, y, θ) on EuclideanManifold(3) for 2D graphs, handled natively and not lifted into SE(3)), one
 * RelativePoseFactor / RelativePose2dFactor per edge with its information, the gauge removed as
 * requested; the values copied back; the reference cost ½ Σ rᵀΛr of the edges; and the solver
 * options that suit these problems. Initial values: swba/problems/pose_graph_init.h. */
#pragma once

#include <swba/core/loss.h>
#include <swba/core/names.h>
#include <swba/factors/relative_pose.h>
#include <swba/io/g2o.h>
#include <swba/nonlinear/problem.h>
#include <swba/nonlinear/solver.h>

#include <array>
#include <map>
#include <memory>
#include <string>

namespace swba::problems
{
/** How the gauge (global pose freedom) is removed. */
enum class PoseGraphGauge
{
	Fixed,  ///< vertices of FIX lines constant; if there are none, the vertex with the lowest id
	Prior,  ///< FIX lines honoured; if there are none, a strong prior on the lowest-id vertex
	Free    ///< only FIX lines; the remaining freedom is left to the LM damping
};
/** "fixed" as for every other gauge option; "fix" (the g2o keyword) is accepted as well. */
constexpr std::array<EnumName<PoseGraphGauge>, 4> enum_names(PoseGraphGauge)
{
	return {{{PoseGraphGauge::Fixed, "fixed"},
			 {PoseGraphGauge::Prior, "prior"},
			 {PoseGraphGauge::Free, "free"},
			 {PoseGraphGauge::Fixed, "fix", true}}};
}
/** Parses "fixed" (or "fix"), "prior", "free"; throws std::invalid_argument otherwise. */
PoseGraphGauge parse_pose_graph_gauge(const std::string& name);
std::string to_string(PoseGraphGauge gauge);

struct PoseGraphProblemOptions
{
	PoseGraphGauge gauge = PoseGraphGauge::Fixed;
	/** Standard deviation of the gauge prior, in metres and radians (W = I/σ). Default 1e-3. */
	double prior_sigma = 1e-3;
	/** Robust loss for every edge (null = plain least squares). Default null. */
	std::shared_ptr<const LossFunction> loss;
	/** Rotation error of 3D edges (relative_pose.h). Default G2o: 2·vec(q_ab⁻¹·q_a⁻¹·q_b). */
	RotationError rotation_error = RotationError::G2o;
};

/** Parses "g2o", "ceres" (RotationError::CeresExample); throws std::invalid_argument otherwise. */
RotationError parse_rotation_error(const std::string& name);

/** A Problem built from a PoseGraph, with the map from g2o ids to variables. */
struct PoseGraphProblem
{
	Problem problem;
	std::map<io::G2oId, VariableId> variable_of;
	int num_constant = 0;  ///< vertices held constant (gauge or FIX)
	bool has_prior = false;
};

/** One variable per vertex (SE3Manifold, or (x, y, θ) on EuclideanManifold(3) for 2D), one
 * RelativePoseFactor / RelativePose2dFactor per edge with its information, gauge as requested.
 * Throws std::invalid_argument on an empty graph. */
PoseGraphProblem build_pose_graph_problem(const io::PoseGraph& graph, const PoseGraphProblemOptions& options = {});

/** Copies the problem's variable values back into the graph's vertices. */
void update_pose_graph(io::PoseGraph& graph, const PoseGraphProblem& problem);

/** Cost of the reference model, ½ Σ rᵀΛr over all edges (no loss, no prior), at the graph's
 * vertex values; r as in relative_pose.h, computed here independently with quaternion algebra.
 * Used to compare peers whatever they report themselves. */
double pose_graph_cost(const io::PoseGraph& graph, RotationError rotation_error = RotationError::G2o);

/** SolverOptions for pose graphs, as `swba pgo` uses them (doc/benchmarks/pgo.md, "Performance"): max_iterations
 * 100, dense_max_dim 200 (pose-graph normal equations are very sparse: CHOLMOD beyond 200 unknowns),
 * initial_trust_region_radius kPoseGraphInitialTrustRegion (a nearly Gauss-Newton first step; LM
 * still shrinks it after a rejected step); everything else SolverOptions' defaults. */
constexpr double kPoseGraphInitialTrustRegion = 1e12;
constexpr int kPoseGraphDenseMaxDim = 200;
SolverOptions pose_graph_solver_options();
}  // namespace swba::problems
