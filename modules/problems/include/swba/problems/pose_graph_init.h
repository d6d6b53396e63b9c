/** \file pose_graph_init.h
 * Initial values for pose-graph optimisation, computed from the edges alone (doc/pgo.md, "Initialisation").
 *
 * - File: the vertex values as read (no change).
 * - Odometry: the poses composed along a spanning tree of the edges, built from the edges between
 *   consecutive ids first (the odometry chain), then the others in file order.
 * - Chordal: chordal relaxation of the rotations (Martinec & Pajdla 2007; Carlone et al. 2015,
 *   "Initialization techniques for 3D SLAM"): R_b ≈ R_a·R_ab is linear in the entries of the
 *   rotation matrices; the 3 rows of R (3D) or (cos θ, sin θ) (2D) are least-squares estimates from
 *   ONE sparse Cholesky factorisation (3×3 / 2×2 blocks, CHOLMOD through swba::BlockCholesky), each
 *   then projected onto SO(3) (SVD, det +1) or the unit circle. Each edge is weighted by a scalar,
 *   the mean diagonal of the rotation block of its information (trace/3 in 3D, Λ_θθ in 2D).
 *   Then, optionally, the positions: with the rotations held, the reference cost ½ Σ rᵀΛr
 *   is quadratic in the positions, and its exact minimiser (cross terms Λ_tr included) is one more
 *   sparse solve of the same size.
 *
 * Anchors keep their values: the FIX vertices, or (no FIX lines) the lowest-id vertex — the same
 * vertex the default gauge of build_pose_graph_problem (pose_graph.h) holds constant. A connected
 * component that contains no anchor (a disconnected graph, a vertex without edges) is anchored at its
 * lowest-id vertex, which keeps its file value (counted in PoseGraphInitSummary::extra_anchors). */
#pragma once

#include <swba/core/names.h>
#include <swba/factors/relative_pose.h>
#include <swba/io/g2o.h>

#include <array>
#include <string>

namespace swba::problems
{
enum class PoseGraphInit
{
	File,      ///< the file's vertex values
	Odometry,  ///< composition along a spanning tree, odometry (consecutive-id) edges first
	Chordal    ///< chordal rotations, then positions by linear least squares (default)
};
constexpr std::array<EnumName<PoseGraphInit>, 3> enum_names(PoseGraphInit)
{
	return {{{PoseGraphInit::Chordal, "chordal"}, {PoseGraphInit::Odometry, "odometry"}, {PoseGraphInit::File, "file"}}};
}
/** Parses "file", "odometry", "chordal"; throws std::invalid_argument otherwise. */
PoseGraphInit parse_pose_graph_init(const std::string& name);
std::string to_string(PoseGraphInit init);

struct PoseGraphInitOptions
{
	/** Method. Default Chordal (fewer LM iterations on every shipped graph, doc/pgo.md). */
	PoseGraphInit method = PoseGraphInit::Chordal;
	/** Chordal only: also solve the positions given the rotations (true), or compose them along the
	 * odometry spanning tree with the chordal rotations (false). Default true. */
	bool solve_positions = true;
	/** Rotation error of the model that the position solve minimises exactly (3D only). Default G2o. */
	RotationError rotation_error = RotationError::G2o;
};

struct PoseGraphInitSummary
{
	PoseGraphInit method = PoseGraphInit::File;
	int num_components = 0;  ///< connected components of the edge graph (isolated vertices included)
	int num_anchors = 0;     ///< vertices that kept their values
	int extra_anchors = 0;   ///< of them, lowest-id vertices of components without FIX/first vertex
	double time_s = 0;       ///< wall time of initialize_pose_graph
	/** One line, e.g. "chordal: 2500 vertices, 1 component, 1 anchor, 0.051 s". */
	std::string brief() const;
};

/** Overwrites the non-anchor vertex values of `graph` with the chosen initial values.
 * Throws std::runtime_error if a linear system cannot be factorised (degenerate information), or naming
 * the first vertex the method gave a non-finite value (information matrices so large that its
 * computation overflows). */
PoseGraphInitSummary initialize_pose_graph(io::PoseGraph& graph, const PoseGraphInitOptions& options = {});
}  // namespace swba::problems
