// The gauge of the range-bearing graph: the six global rigid motions under which its cost is
// invariant, in each variable's tangent coordinates, and the free gauge's hold on them (the motion a
// solve made along them is undone, so the window keeps one frame from step to step).
#include "range_bearing_graph.h"

#include <swba/core/lie.h>
#include <swba/core/manifold.h>
#include <swba/factors/planar.h>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

namespace swba::estimators::detail
{
Eigen::MatrixXd RangeBearingGraph::gauge_directions(VariableId v, const double* x) const
{
	const auto& var = smoother_.problem().variable(v);
	// Rows in the base manifold's tangent coordinates; a planar variable keeps some of them.
	const auto* sub = dynamic_cast<const SubspaceManifold*>(var.manifold.get());
	const int base_size = sub ? sub->base()->tangent_size() : var.manifold->tangent_size();
	Eigen::MatrixXd B = Eigen::MatrixXd::Zero(base_size, 6);
	if (base_size == 6)
	{
		// The global motion p ↦ p + u + w × p as a right perturbation of T = [R | t]:
		// δρ = Rᵀ(u + w × t), δω = Rᵀw.
		const auto T = se3_view(x);
		const Eigen::Matrix3d Rt = T.leftCols<3>().transpose();
		B.block<3, 3>(0, 0) = Rt;
		B.block<3, 3>(0, 3) = -Rt * skew(T.col(3));
		B.block<3, 3>(3, 3) = Rt;
	}
	else if (is_world_point(v))
	{
		const Eigen::Vector3d p(x[0], x[1], x[2]);
		B.block<3, 3>(0, 0) = Eigen::Matrix3d::Identity();
		B.block<3, 3>(0, 3) = -skew(p);
	}
	// An inverse-depth landmark is relative to its anchor pose: invariant, zero rows.
	Eigen::MatrixXd N(var.manifold->tangent_size(), 6);
	for (int i = 0; i < var.manifold->tangent_size(); i++) N.row(i) = B.row(sub ? sub->coordinates()[i] : i);
	// A planar model moves only along x, y and the yaw about z: the other motions are no gauge of it.
	if (model_ == PoseModel::Planar) N.middleCols<3>(2).setZero();
	return N;
}

std::map<VariableId, std::vector<double>> RangeBearingGraph::gauge_snapshot() const
{
	std::map<VariableId, std::vector<double>> out;
	for (const auto& [v, var] : smoother_.problem().variables())
		if (!var.constant || (smoother_.in_prior(v) && smoother_.prior().index_of(v) < 0))  // stored ones hold it too
		{
			const double* x = smoother_.linearization_point(v);
			out.emplace(v, std::vector<double>(x, x + var.value.size()));
		}
	return out;
}

void RangeBearingGraph::hold_gauge(const std::map<VariableId, std::vector<double>>& before)
{
	Problem& problem = smoother_.problem();
	// The rigid motion ξ = [u, w] that best explains the displacement d of the variables since
	// `before` (least squares in their tangent coordinates): Σ NᵢᵀNᵢ ξ = Σ Nᵢᵀ dᵢ.
	Eigen::Matrix<double, 6, 6> A = Eigen::Matrix<double, 6, 6>::Zero();
	Eigen::Matrix<double, 6, 1> g = Eigen::Matrix<double, 6, 1>::Zero();
	for (const auto& [v, x0] : before)
	{
		if (!problem.has_variable(v)) continue;
		const auto& var = problem.variable(v);
		Eigen::VectorXd d(var.manifold->tangent_size());
		var.manifold->minus(var.value.data(), x0.data(), d.data());
		const Eigen::MatrixXd N = gauge_directions(v, x0.data());
		A += N.transpose() * N;
		g += N.transpose() * d;
	}
	// Planar: the motions off the plane (u_z, w_x, w_y) have zero columns; held at zero, the fit and
	// the motion undone are a planar rigid motion (x, y, yaw), which keeps every variable on its plane.
	if (model_ == PoseModel::Planar)
		for (int c = 2; c < 5; c++) A(c, c) = 1.0;
	Eigen::LDLT<Eigen::Matrix<double, 6, 6>> ldlt(A);
	if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0)) return;  // nothing spans the gauge
	const Eigen::Matrix<double, 6, 1> xi = ldlt.solve(g);
	// Undo it: every pose and world point moves by p ↦ R p + t with R = Exp(−w), t = −u (inverse-depth
	// landmarks are relative to their anchors and do not move). The window's factors are invariant.
	const Eigen::Vector3d w = -xi.tail<3>();
	const Eigen::Matrix3d R =
		w.norm() > 0 ? Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix() : Eigen::Matrix3d::Identity();
	const Eigen::Vector3d t = -xi.head<3>();
	for (const auto& [v, var] : problem.variables())
	{
		if (var.constant) continue;
		std::vector<double> x = var.value;
		if (var.value.size() == SE3Manifold::kAmbient)
		{
			auto T = se3_view(x.data());
			T.leftCols<3>() = R * T.leftCols<3>().eval();
			T.col(3) = R * T.col(3).eval() + t;
		}
		else if (is_world_point(v))
		{
			Eigen::Map<Eigen::Vector3d> p(x.data());
			p = R * p.eval() + t;
		}
		else
			continue;
		problem.set_value(v, x.data());
	}
}
}  // namespace swba::estimators::detail
