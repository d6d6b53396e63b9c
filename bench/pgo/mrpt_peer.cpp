// The MRPT peer: mrpt::graphslam::optimize_graph_spa_levmarq on MRPT's network of poses, from the
// file's values, rooted at the lowest id.
#include <mrpt/graphs/CNetworkOfPoses.h>
#include <mrpt/graphslam/levmarq.h>
#include <mrpt/poses/CPose3DQuat.h>

#include <algorithm>

#include "pgo_peers.h"

namespace swba::bench
{
namespace
{
using mrpt::graphs::TNodeID;

mrpt::poses::CPose3D to_pose(const Eigen::Vector3d& t, const Eigen::Quaterniond& q)
{
	return mrpt::poses::CPose3D(
		mrpt::poses::CPose3DQuat(t.x(), t.y(), t.z(), mrpt::math::CQuaternionDouble(q.w(), q.x(), q.y(), q.z())));
}

mrpt::poses::CPose3D to_pose(const io::PoseGraphVertex3& v) { return to_pose(v.t, v.q); }
mrpt::poses::CPose2D to_pose(const io::PoseGraphVertex2& v) { return mrpt::poses::CPose2D(v.x, v.y, v.theta); }

mrpt::poses::CPose3DPDFGaussianInf to_pdf(const io::PoseGraphEdge3& e)
{
	mrpt::poses::CPose3DPDFGaussianInf pdf;
	pdf.mean = to_pose(e.t, e.q);
	// MRPT's levmarq whitens the pseudo-log [t; ω] with cov_inv as is, so the g2o information,
	// ordered (x, y, z, qx, qy, qz) ≈ (t, ω), is passed unpermuted.
	pdf.cov_inv.asEigen() = e.information;
	return pdf;
}

mrpt::poses::CPosePDFGaussianInf to_pdf(const io::PoseGraphEdge2& e)
{
	mrpt::poses::CPosePDFGaussianInf pdf;
	pdf.mean = mrpt::poses::CPose2D(e.x, e.y, e.theta);
	pdf.cov_inv.asEigen() = e.information;
	return pdf;
}

void from_pose(const mrpt::poses::CPose3D& P, io::PoseGraphVertex3& v)
{
	v.t = Eigen::Vector3d(P.x(), P.y(), P.z());
	v.q = Eigen::Quaterniond(Eigen::Matrix3d(P.getRotationMatrix().asEigen())).normalized();
}
void from_pose(const mrpt::poses::CPose2D& P, io::PoseGraphVertex2& v) { v = {P.x(), P.y(), P.phi()}; }

/** The vertices and edges of one dimension as MRPT's network (setup), optimised (solve), copied back. */
template <typename Network, typename Vertices, typename Edges>
void solve_network(Vertices& vertices, const Edges& edges, io::G2oId root, const mrpt::containers::yaml& params,
				   mrpt::graphslam::TResultInfoSpaLevMarq& info, Result& res)
{
	auto t0 = SteadyClock::now();
	Network G;
	for (const auto& [id, v] : vertices) G.nodes[static_cast<TNodeID>(id)] = to_pose(v);
	for (const auto& e : edges) G.insertEdge(static_cast<TNodeID>(e.from), static_cast<TNodeID>(e.to), to_pdf(e));
	G.root = static_cast<TNodeID>(root);
	res.setup_s = seconds_since(t0);
	t0 = SteadyClock::now();
	mrpt::graphslam::optimize_graph_spa_levmarq(G, info, nullptr, params);
	res.solve_s = seconds_since(t0);
	for (auto& [id, v] : vertices) from_pose(G.nodes.at(static_cast<TNodeID>(id)), v);
}
}  // namespace

Result run_mrpt(const io::PoseGraph& input, const Settings& s)
{
	Result res;
	res.solver = "mrpt";
	io::PoseGraph g = input;
	try
	{
		mrpt::graphslam::TResultInfoSpaLevMarq info;
		mrpt::containers::yaml params;
		params["max_iterations"] = s.mrpt_max_iterations;
		if (!g.is_2d())
			solve_network<mrpt::graphs::CNetworkOfPoses3DInf>(g.vertices3, g.edges3, g.vertices3.begin()->first, params,
															  info, res);
		else
			solve_network<mrpt::graphs::CNetworkOfPoses2DInf>(g.vertices2, g.edges2, g.vertices2.begin()->first, params,
															  info, res);
		res.iterations = static_cast<int>(info.num_iters);
		res.reported_cost = info.final_total_sq_error;
		res.final_cost = 0;  // evaluated per model by the caller
		res.solution = g;
		res.note = "solver's cost = MRPT's own unweighted sum of squared errors";
	}
	catch (const std::exception& e)
	{
		std::string what = e.what();
		std::replace(what.begin(), what.end(), '\n', ' ');
		res.note = "FAILED: " + what.substr(0, 200);
	}
	return res;
}
}  // namespace swba::bench
