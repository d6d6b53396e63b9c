// g2o pose graph → swba::Problem, back, and the reference cost.
#include <swba/core/lie.h>
#include <swba/core/manifold.h>
#include <swba/factors/relative_pose.h>
#include <swba/problems/pose_graph.h>

#include "pose_graph_residual.h"

#include <cmath>
#include <stdexcept>

namespace swba::problems
{
namespace
{
void to_storage(const io::PoseGraphVertex3& v, double* x)
{
	auto T = se3_view(x);
	T.leftCols<3>() = v.q.toRotationMatrix();
	T.col(3) = v.t;
}

/** Adds the factor of edge e (its information, between its two vertices). */
template <class Edge>
void add_edge_factor(const std::shared_ptr<Factor>& f, const Edge& e, const PoseGraphProblemOptions& opt,
					 PoseGraphProblem& out)
{
	f->set_information(e.information);
	out.problem.add_factor(f, {out.variable_of.at(e.from), out.variable_of.at(e.to)}, opt.loss);
}

void add_vertices_and_edges(const io::PoseGraph& g, const PoseGraphProblemOptions& opt, PoseGraphProblem& out)
{
	Problem& P = out.problem;
	const auto se3 = SE3Manifold::instance();
	const auto r3 = euclidean_manifold(3);
	double x[SE3Manifold::kAmbient];
	for (const auto& [id, v] : g.vertices3)
	{
		to_storage(v, x);
		out.variable_of[id] = P.add_variable(x, se3);
	}
	for (const auto& [id, v] : g.vertices2)
	{
		const double p[3] = {v.x, v.y, v.theta};
		out.variable_of[id] = P.add_variable(p, r3);
	}
	for (const auto& e : g.edges3)
		add_edge_factor(std::make_shared<RelativePoseFactor>(e.q, e.t, opt.rotation_error), e, opt, out);
	for (const auto& e : g.edges2) add_edge_factor(std::make_shared<RelativePose2dFactor>(e.x, e.y, e.theta), e, opt, out);
}

/** FIX vertices constant; without FIX lines, the lowest-id vertex held by the requested gauge. */
void remove_gauge(const io::PoseGraph& g, const PoseGraphProblemOptions& opt, PoseGraphProblem& out)
{
	Problem& P = out.problem;
	for (io::G2oId id : g.fixed) P.set_constant(out.variable_of.at(id));
	const io::G2oId first = out.variable_of.begin()->first;
	if (!g.fixed.empty()) return;
	if (opt.gauge == PoseGraphGauge::Fixed)
		P.set_constant(out.variable_of.at(first));
	else if (opt.gauge == PoseGraphGauge::Prior)
	{
		std::shared_ptr<Factor> prior;
		if (g.is_2d())
		{
			const auto& v = g.vertices2.at(first);
			prior = std::make_shared<PosePrior2dFactor>(v.x, v.y, v.theta);
		}
		else
		{
			const auto& v = g.vertices3.at(first);
			prior = std::make_shared<PosePriorQuatFactor>(v.q, v.t);
		}
		prior->set_sigma(opt.prior_sigma);
		P.add_factor(prior, {out.variable_of.at(first)});
		out.has_prior = true;
	}
}
}  // namespace

PoseGraphGauge parse_pose_graph_gauge(const std::string& name) { return parse_enum<PoseGraphGauge>(name, "gauge"); }

std::string to_string(PoseGraphGauge gauge) { return enum_name(gauge); }

RotationError parse_rotation_error(const std::string& name) { return parse_enum<RotationError>(name, "rotation error"); }

PoseGraphProblem build_pose_graph_problem(const io::PoseGraph& g, const PoseGraphProblemOptions& opt)
{
	if (g.num_vertices() == 0) throw std::invalid_argument("pose graph has no vertices");
	if (!(opt.prior_sigma > 0)) throw std::invalid_argument("prior_sigma must be > 0");
	PoseGraphProblem out;
	add_vertices_and_edges(g, opt, out);
	remove_gauge(g, opt, out);
	for (const auto& [id, var] : out.variable_of) out.num_constant += out.problem.is_constant(var) ? 1 : 0;
	return out;
}

void update_pose_graph(io::PoseGraph& g, const PoseGraphProblem& pp)
{
	for (auto& [id, v] : g.vertices3)
	{
		const auto T = se3_view(pp.problem.value(pp.variable_of.at(id)));
		v.q = Eigen::Quaterniond(Eigen::Matrix3d(T.leftCols<3>())).normalized();
		v.t = T.col(3);
	}
	for (auto& [id, v] : g.vertices2)
	{
		const double* p = pp.problem.value(pp.variable_of.at(id));
		v.x = p[0];
		v.y = p[1];
		v.theta = wrap_to_pi(p[2]);
	}
}

double pose_graph_cost(const io::PoseGraph& g, RotationError rotation_error)
{
	double cost = 0;
	for (const auto& e : g.edges3)
	{
		const auto& a = g.vertices3.at(e.from);
		const auto& b = g.vertices3.at(e.to);
		Eigen::Matrix<double, 6, 1> r;
		r.head<3>() = a.q.conjugate() * (b.t - a.t) - e.t;
		r.tail<3>() = detail::rotation_residual(e.q, a.q, b.q, rotation_error);
		cost += 0.5 * r.dot(e.information * r);
	}
	for (const auto& e : g.edges2)
	{
		const auto& a = g.vertices2.at(e.from);
		const auto& b = g.vertices2.at(e.to);
		const double c = std::cos(a.theta), s = std::sin(a.theta);
		const double dx = b.x - a.x, dy = b.y - a.y;
		const Eigen::Vector3d r(c * dx + s * dy - e.x, -s * dx + c * dy - e.y,
								wrap_to_pi(b.theta - a.theta - e.theta));
		cost += 0.5 * r.dot(e.information * r);
	}
	return cost;
}

SolverOptions pose_graph_solver_options()
{
	SolverOptions o;
	o.max_iterations = 100;
	o.dense_max_dim = kPoseGraphDenseMaxDim;
	o.initial_trust_region_radius = kPoseGraphInitialTrustRegion;
	return o;
}
}  // namespace swba::problems
