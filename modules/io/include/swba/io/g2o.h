/** \file g2o.h
 * g2o pose graphs: reading and writing (the problem they define, its cost and its initial values:
 * swba/problems/pose_graph.h, swba/problems/pose_graph_init.h).
 *
 * Supported lines (whitespace separated, one element per line):
 *   VERTEX_SE3:QUAT id x y z qx qy qz qw
 *   EDGE_SE3:QUAT   i j x y z qx qy qz qw  I11 I12 … I16 I22 … I66   (21 upper-triangular entries,
 *                   ordered x, y, z, qx, qy, qz)
 *   VERTEX_SE2 id x y θ
 *   EDGE_SE2   i j x y θ  I11 I12 I13 I22 I23 I33
 *   FIX id [id …]
 * Blank lines and lines starting with '#' are ignored; lines with any other tag are skipped and
 * counted (PoseGraph::skipped_tags). A file holds either 2D or 3D elements, not both.
 * Quaternions (vertices and edges) are normalised on read. Errors (std::runtime_error) name the
 * source and the line: malformed or non-finite numbers, missing or extra fields, unknown vertex ids
 * in edges or FIX lines, duplicate vertex ids, zero quaternions, information matrices that are not
 * positive definite (unless G2oReadOptions::information is Repair: see InformationPolicy).
 *
 * 2D graphs are kept as 2D (poses (x, y, θ)), not lifted into SE(3). */
#pragma once

#include <swba/core/names.h>
#include <swba/core/positive_definite.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <iosfwd>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace swba::io
{
using G2oId = std::int64_t;

/** What the reader does with an edge information matrix that is not positive definite (no Cholesky
 * factor). Files produced by some front ends (e.g. SE-Sync's cubicle.g2o) hold indefinite ones. */
enum class InformationPolicy
{
	Strict,  ///< refuse: an error naming file:line, the smallest eigenvalue and the repair option
	Repair   ///< replace it by the nearest positive-definite matrix (swba/core/positive_definite.h) and count it
};
constexpr std::array<EnumName<InformationPolicy>, 2> enum_names(InformationPolicy)
{
	return {{{InformationPolicy::Strict, "strict"}, {InformationPolicy::Repair, "repair"}}};
}

struct G2oReadOptions
{
	/** Default Strict (an indefinite information is an error). */
	InformationPolicy information = InformationPolicy::Strict;
	/** Repair only: eigenvalue floor relative to the largest eigenvalue. Default 1e-6
	 * (kPositiveDefiniteRelativeFloor; why: swba/core/positive_definite.h). */
	double relative_floor = kPositiveDefiniteRelativeFloor;
};

/** The information matrices the reader repaired (InformationPolicy::Repair). */
struct InformationRepairs
{
	int count = 0;                     ///< edges whose information was replaced
	double min_eigenvalue = 0;         ///< the most negative eigenvalue among them (0 if none)
	int min_eigenvalue_line = 0;       ///< its source line
	std::vector<int> lines;            ///< source line of every repaired edge, in file order
	/** "repaired N of M edge information matrices (not positive definite; eigenvalues below 1e-06 x the
	 * largest raised to it; most negative eigenvalue -1.6e+05 at line L)"; M = `num_edges`. */
	std::string summary(size_t num_edges, double relative_floor) const;
};

struct PoseGraphVertex3
{
	Eigen::Vector3d t = Eigen::Vector3d::Zero();
	Eigen::Quaterniond q = Eigen::Quaterniond::Identity();  ///< unit
};
struct PoseGraphVertex2
{
	double x = 0, y = 0, theta = 0;
};
struct PoseGraphEdge3
{
	G2oId from = 0, to = 0;
	Eigen::Vector3d t = Eigen::Vector3d::Zero();             ///< t_ab, pose `to` in frame `from`
	Eigen::Quaterniond q = Eigen::Quaterniond::Identity();  ///< q_ab, unit
	Eigen::Matrix<double, 6, 6> information = Eigen::Matrix<double, 6, 6>::Identity();  ///< (x,y,z,qx,qy,qz)
	int line = 0;  ///< source line (0 when built in code)
};
struct PoseGraphEdge2
{
	G2oId from = 0, to = 0;
	double x = 0, y = 0, theta = 0;
	Eigen::Matrix3d information = Eigen::Matrix3d::Identity();  ///< (x, y, θ)
	int line = 0;
};

/** A pose graph as read from a g2o file. Exactly one of the 2D/3D containers is used. */
struct PoseGraph
{
	std::map<G2oId, PoseGraphVertex3> vertices3;
	std::map<G2oId, PoseGraphVertex2> vertices2;
	std::vector<PoseGraphEdge3> edges3;
	std::vector<PoseGraphEdge2> edges2;
	std::set<G2oId> fixed;                   ///< FIX lines
	std::map<std::string, int> skipped_tags; ///< unknown tag → number of lines skipped
	InformationRepairs repaired_information; ///< empty unless read with InformationPolicy::Repair

	bool is_2d() const { return !vertices2.empty() || !edges2.empty(); }
	size_t num_vertices() const { return vertices3.size() + vertices2.size(); }
	size_t num_edges() const { return edges3.size() + edges2.size(); }
	/** "skipped 3 line(s) with unknown tag(s): PARAMS_SE3OFFSET x1, EDGE_SE3_PRIOR x2" (a tag cut to 40
	 * characters), or "". */
	std::string skipped_summary() const;
	/** The first vertex (2D, then 3D; id order) with a non-finite value, "vertex 1 (x y theta = 1 nan 0)", or
	 * "" when every value is finite. */
	std::string first_non_finite_vertex() const;
};

/** Reads a g2o file; throws std::runtime_error("<path>:<line>: <reason>") on malformed input
 * (std::invalid_argument on invalid options). */
PoseGraph read_g2o(const std::string& path, const G2oReadOptions& options = {});
/** Same, from a stream; `source_name` prefixes error messages. */
PoseGraph read_g2o(std::istream& in, const std::string& source_name = "<stream>", const G2oReadOptions& options = {});

/** Writes vertices (in id order), edges (in stored order) and FIX lines with %.17g, so that a
 * read → write → read round trip reproduces every number to the last bit of the normalised values.
 * Throws std::runtime_error naming the first non-finite vertex (and the path) before writing anything:
 * the reader refuses such a file. */
void write_g2o(const PoseGraph& graph, const std::string& path);
void write_g2o(const PoseGraph& graph, std::ostream& out);
}  // namespace swba::io
