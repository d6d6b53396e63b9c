// Marginal covariances of the range-bearing graph: the free gauge's hold, the planar embedding and the
// landmarks' world positions (an inverse-depth landmark through its anchor pose).
#include "range_bearing_graph.h"

#include <swba/core/lie.h>
#include <swba/core/manifold.h>
#include <swba/factors/planar.h>

#include <exception>
#include <limits>

namespace swba::estimators::detail
{
namespace
{
/** The rows of variable `v`'s tangent in its base manifold's tangent (planar: a subset). */
std::vector<int> base_coordinates(const Manifold& m)
{
	if (const auto* sub = dynamic_cast<const SubspaceManifold*>(&m)) return sub->coordinates();
	std::vector<int> all(static_cast<std::size_t>(m.tangent_size()));
	for (int i = 0; i < m.tangent_size(); i++) all[static_cast<std::size_t>(i)] = i;
	return all;
}

/** `block` (tangent × tangent of variables with coordinates `ca`, `cb`) embedded in a `n`×`n` matrix. */
Eigen::MatrixXd embed(const Eigen::MatrixXd& block, const std::vector<int>& ca, const std::vector<int>& cb, int n)
{
	Eigen::MatrixXd out = Eigen::MatrixXd::Zero(n, n);
	for (std::size_t i = 0; i < ca.size(); i++)
		for (std::size_t j = 0; j < cb.size(); j++)
			out(ca[i], cb[j]) = block(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j));
	return out;
}
}  // namespace

CovarianceResult RangeBearingGraph::covariances(CovarianceRequest request)
{
	Problem& problem = smoother_.problem();
	VariableId hold = -1;
	if (opt_.gauge == GaugeMode::Free && !smoother_.states().empty())
	{
		const VariableId initial = poses_.front().var;
		if (problem.has_variable(initial))
			hold = initial;
		else
		{
			hold = smoother_.states().front().var;
			for (const auto& [v, var] : problem.variables())
				if (!var.constant) request.gauge[v] = gauge_directions(v, smoother_.linearization_point(v));
		}
		problem.set_constant(hold, true);
	}
	// A covariance that cannot be computed is reported (NaN), never a failure of the estimate.
	CovarianceResult r;
	try
	{
		r = smoother_.covariances(request);
	}
	catch (const std::exception& e)
	{
		r = CovarianceResult{};
		r.message = e.what();
	}
	if (hold >= 0) problem.set_constant(hold, false);
	return r;
}

PoseCovariance RangeBearingGraph::pose_covariance(const CovarianceResult& r, std::size_t g) const
{
	if (!r.ok || g >= r.blocks.size()) return PoseCovariance::Constant(std::numeric_limits<double>::quiet_NaN());
	// Every pose has the model's manifold (one of the linear tail is no longer in the problem).
	const auto c = model_ == PoseModel::Planar ? planar_pose_coordinates() : base_coordinates(SE3Manifold());
	return embed(r.blocks[g], c, c, 6);
}

std::map<std::int32_t, LandmarkEstimate> RangeBearingGraph::landmark_estimates(double* seconds)
{
	std::vector<const Landmark*> all;
	for (const auto& [id, lm] : store_) all.push_back(&lm);
	std::map<std::int32_t, LandmarkEstimate> out = estimates_of(all, seconds);
	for (const auto& [id, m] : store_.map()) out[id] = {m.position, m.covariance};  // never in the state as well
	return out;
}

Eigen::MatrixXd RangeBearingGraph::world_position_jacobian(const Landmark& lm) const
{
	const Problem& problem = smoother_.problem();
	const bool world = opt_.landmarks == LandmarkParameterization::Xyz || lm.world_xyz || model_ == PoseModel::Planar;
	if (world)
	{
		const auto c = base_coordinates(*problem.variable(lm.var).manifold);
		Eigen::MatrixXd J = Eigen::MatrixXd::Zero(3, static_cast<Eigen::Index>(c.size()));
		for (std::size_t i = 0; i < c.size(); i++) J(c[i], static_cast<Eigen::Index>(i)) = 1;
		return J;
	}
	// p = R_a (R_s l(λ) + t_s) + t_a: ∂p/∂λ = R_a R_s ∂l/∂λ (central differences), and with the
	// anchor's right perturbation ∂p/∂ρ = R_a, ∂p/∂ω = −R_a [q]× (q = R_s l + t_s).
	const auto& anchor = poses_[lm.anchor_step];
	const double* xa = problem.value(anchor.var);
	const Eigen::Vector3d lam = Eigen::Map<const Eigen::Vector3d>(problem.value(lm.var));
	const auto Ta = se3_view(xa);
	const Eigen::Matrix3d Ra = Ta.leftCols<3>();
	Eigen::MatrixXd J(3, 9);
	for (int k = 0; k < 3; k++)
	{
		const double h = 1e-6 * std::max(1.0, std::abs(lam[k]));
		Eigen::Vector3d lp = lam, lm_ = lam;
		lp[k] += h;
		lm_[k] -= h;
		J.col(k) = (inverse_depth_to_world(xa, anchor.sensor, lp) - inverse_depth_to_world(xa, anchor.sensor, lm_)) / (2 * h);
	}
	const Eigen::Vector3d q = Ra.transpose() * (world_position(lm) - Ta.col(3));
	J.middleCols<3>(3) = Ra;
	J.rightCols<3>() = -Ra * skew(q);
	return J;
}

std::map<std::int32_t, LandmarkEstimate> RangeBearingGraph::estimates_of(const std::vector<const Landmark*>& lms,
																		 double* seconds)
{
	CovarianceRequest request;  // naming stored prior-only landmarks, it brings them back into the prior
	const std::vector<const Landmark*>& order = lms;
	for (const Landmark* l : lms)
	{
		const Landmark& lm = *l;
		const bool world = opt_.landmarks == LandmarkParameterization::Xyz || lm.world_xyz || model_ == PoseModel::Planar;
		if (world)
			request.groups.push_back({lm.var});
		else
			request.groups.push_back({lm.var, poses_[lm.anchor_step].var});
	}
	const CovarianceResult r = covariances(request);
	if (seconds) *seconds = r.seconds;
	std::map<std::int32_t, LandmarkEstimate> out;
	for (std::size_t g = 0; g < order.size(); g++)
	{
		const Landmark& lm = *order[g];
		LandmarkEstimate& e = out[lm.id];
		e.position = world_position(lm);
		if (!r.ok)
		{
			e.covariance.setConstant(std::numeric_limits<double>::quiet_NaN());
			continue;
		}
		const Eigen::MatrixXd J = world_position_jacobian(lm);
		e.covariance = J * r.blocks[g] * J.transpose();
		e.covariance = 0.5 * (e.covariance + e.covariance.transpose()).eval();
	}
	return out;
}
}  // namespace swba::estimators::detail
