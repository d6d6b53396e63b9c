// The Ceres 2.1 peer: the reference pose-graph model as automatically differentiated cost functors
// (how Ceres's users write it), SPARSE_NORMAL_CHOLESKY, from the file's values.
#include <ceres/ceres.h>

#include <algorithm>
#include <array>
#include <map>
#include <set>

#include "pgo_peers.h"

namespace swba::bench
{
namespace
{
/** Reference 3D model: r = Lᵀ·[R_aᵀ(t_b − t_a) − t_ab ; 2·vec(δq)], Λ = L·Lᵀ, with
 * δq = q_ab⁻¹·q_a⁻¹·q_b (g2o) or q_ab·(q_a⁻¹·q_b)⁻¹ (Ceres's pose_graph_3d example). */
struct ReferencePose3dCost
{
	ReferencePose3dCost(const io::PoseGraphEdge3& e, RotationError model)
		: t_ab(e.t), q_ab(e.q), g2o(model == RotationError::G2o)
	{
		W = e.information.llt().matrixL().transpose();
	}
	template <typename T>
	bool operator()(const T* pa, const T* qa, const T* pb, const T* qb, T* residual) const
	{
		const Eigen::Map<const Eigen::Matrix<T, 3, 1>> p_a(pa), p_b(pb);
		const Eigen::Map<const Eigen::Quaternion<T>> q_a(qa), q_b(qb);
		const Eigen::Quaternion<T> q_a_inv = q_a.conjugate();
		const Eigen::Quaternion<T> q_est = q_a_inv * q_b;
		const Eigen::Quaternion<T> dq = g2o ? Eigen::Quaternion<T>(q_ab.conjugate().template cast<T>() * q_est)
											: Eigen::Quaternion<T>(q_ab.template cast<T>() * q_est.conjugate());
		Eigen::Map<Eigen::Matrix<T, 6, 1>> r(residual);
		r.template head<3>() = q_a_inv * (p_b - p_a) - t_ab.template cast<T>();
		r.template tail<3>() = T(2.0) * dq.vec();
		r.applyOnTheLeft(W.template cast<T>());
		return true;
	}
	Eigen::Vector3d t_ab;
	Eigen::Quaterniond q_ab;
	bool g2o;
	Eigen::Matrix<double, 6, 6> W;
	EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

template <typename T>
T normalize_angle(const T& a)
{
	const T two_pi(2.0 * M_PI);
	return a - two_pi * ceres::floor((a + T(M_PI)) / two_pi);
}

/** Reference 2D model: r = Lᵀ·[R(θ_a)ᵀ(p_b − p_a) − p_ab ; wrap(θ_b − θ_a − θ_ab)]. */
struct ReferencePose2dCost
{
	explicit ReferencePose2dCost(const io::PoseGraphEdge2& e) : x(e.x), y(e.y), theta(e.theta)
	{
		W = e.information.llt().matrixL().transpose();
	}
	template <typename T>
	bool operator()(const T* a, const T* b, T* residual) const
	{
		const T c = ceres::cos(a[2]), s = ceres::sin(a[2]);
		const T dx = b[0] - a[0], dy = b[1] - a[1];
		Eigen::Matrix<T, 3, 1> r(c * dx + s * dy - T(x), -s * dx + c * dy - T(y),
								 normalize_angle(b[2] - a[2] - T(theta)));
		Eigen::Map<Eigen::Matrix<T, 3, 1>> out(residual);
		out = W.template cast<T>() * r;
		return true;
	}
	double x, y, theta;
	Eigen::Matrix3d W;
};

/** Parameter storage: 3D p(3) + q(4, Eigen order x y z w); 2D (x, y, θ). */
using Parameters = std::map<io::G2oId, std::array<double, 7>>;

/** The graph as a Ceres problem over `params`; the gauge: FIX lines, else the lowest id (as swba's default). */
void build_problem(const io::PoseGraph& g, RotationError model, Parameters& params, ceres::Problem& problem)
{
	for (const auto& [id, v] : g.vertices3)
	{
		auto& p = params[id];
		for (int i = 0; i < 3; i++) p[i] = v.t[i];
		for (int i = 0; i < 4; i++) p[3 + i] = v.q.coeffs()[i];
	}
	for (const auto& [id, v] : g.vertices2) params[id] = {v.x, v.y, v.theta, 0, 0, 0, 0};
	for (const auto& e : g.edges3)
	{
		double* a = params.at(e.from).data();
		double* b = params.at(e.to).data();
		problem.AddResidualBlock(new ceres::AutoDiffCostFunction<ReferencePose3dCost, 6, 3, 4, 3, 4>(
									 new ReferencePose3dCost(e, model)),
								 nullptr, a, a + 3, b, b + 3);
	}
	for (const auto& e : g.edges2)
		problem.AddResidualBlock(
			new ceres::AutoDiffCostFunction<ReferencePose2dCost, 3, 3, 3>(new ReferencePose2dCost(e)), nullptr,
			params.at(e.from).data(), params.at(e.to).data());
	auto* quaternion_manifold = new ceres::EigenQuaternionManifold;  // owned by the problem
	bool manifold_used = false;
	for (auto& [id, p] : params)
	{
		if (!g.is_2d() && problem.HasParameterBlock(p.data() + 3))
		{
			problem.SetManifold(p.data() + 3, quaternion_manifold);
			manifold_used = true;
		}
	}
	if (!manifold_used) delete quaternion_manifold;
	std::set<io::G2oId> fixed = g.fixed;
	if (fixed.empty()) fixed.insert(params.begin()->first);
	for (auto id : fixed)
	{
		double* p = params.at(id).data();
		if (problem.HasParameterBlock(p)) problem.SetParameterBlockConstant(p);
		if (!g.is_2d() && problem.HasParameterBlock(p + 3)) problem.SetParameterBlockConstant(p + 3);
	}
}

void copy_solution(const Parameters& params, io::PoseGraph& g)
{
	for (auto& [id, v] : g.vertices3)
	{
		const auto& p = params.at(id);
		v.t = Eigen::Vector3d(p[0], p[1], p[2]);
		v.q = Eigen::Quaterniond(p[6], p[3], p[4], p[5]).normalized();
	}
	for (auto& [id, v] : g.vertices2)
	{
		const auto& p = params.at(id);
		v = {p[0], p[1], p[2]};
	}
}
}  // namespace

Result run_ceres(const io::PoseGraph& input, const Settings& s, RotationError model, double initial_trust_region)
{
	Result res;
	res.solver = initial_trust_region > 0 ? "ceres:tr" : "ceres";
	for (int rep = 0; rep < s.repeat; rep++)
	{
		io::PoseGraph g = input;
		auto t0 = SteadyClock::now();
		ceres::Problem problem;
		Parameters params;
		build_problem(g, model, params, problem);
		const double setup = seconds_since(t0);

		ceres::Solver::Options o;
		o.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
		o.max_num_iterations = s.max_iterations;
		o.num_threads = s.threads;
		o.minimizer_progress_to_stdout = false;
		if (initial_trust_region > 0)
		{
			o.initial_trust_region_radius = initial_trust_region;
			o.max_trust_region_radius = std::max(o.max_trust_region_radius, initial_trust_region);
		}
		ceres::Solver::Summary summary;
		t0 = SteadyClock::now();
		ceres::Solve(o, &problem, &summary);
		const double solve = seconds_since(t0);

		copy_solution(params, g);
		res.keep_fastest(rep, setup, solve);
		res.final_cost = problems::pose_graph_cost(g, model);
		res.reported_cost = summary.final_cost;
		res.iterations = static_cast<int>(summary.iterations.size()) - 1;  // iteration 0 is the start
		res.note = summary.BriefReport();
		res.solution = g;
	}
	return res;
}
}  // namespace swba::bench
