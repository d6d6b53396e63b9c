// The map policy's map: landmarks that left the window's state, kept as their marginals, and their
// return to the state when they are seen again.
#include "range_bearing_graph.h"

#include <swba/factors/linear_prior.h>
#include <swba/factors/planar.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>

namespace swba::estimators::detail
{
int RangeBearingGraph::keep_in_map(const std::set<VariableId>& vars)
{
	std::vector<const Landmark*> lms;
	for (VariableId v : vars)
		if (const Landmark* lm = store_.find_by_variable(v)) lms.push_back(lm);
	if (lms.empty()) return 0;
	// The marginal, not the covariance conditioned on the robot's pose when the landmark leaves: that
	// one counts the error the landmark shares with the robot (and, through the window's prior, with
	// every later pose) as known, and on the 5000-step run its map drifted further (doc/window.md).
	const int n = model_ == PoseModel::Planar ? 2 : 3;  // planar: the point's (x, y)
	int lost = 0;
	for (const auto& [id, e] : estimates_of(lms, nullptr))
	{
		const Eigen::Matrix3d C = 0.5 * (e.covariance + e.covariance.transpose());
		if (!C.allFinite() || Eigen::LLT<Eigen::MatrixXd>(C.topLeftCorner(n, n)).info() != Eigen::Success)
		{
			lost++;
			continue;
		}
		store_.keep_in_map(id, {e.position, C});
	}
	return lost;
}

Landmark& RangeBearingGraph::restore_from_map(std::int32_t id)
{
	const MapLandmark m = store_.take_from_map(id);
	Problem& problem = smoother_.problem();
	std::shared_ptr<const Manifold> manifold = euclidean_manifold(3);
	if (model_ == PoseModel::Planar) manifold = planar_point_manifold();
	const int n = manifold->tangent_size();  // planar: (x, y), the point keeps its height
	Landmark lm;
	lm.id = id;
	lm.world_xyz = true;
	lm.var = problem.add_variable(m.position, manifold, Group::Eliminable);
	// r = U (p ⊟ p_map) with UᵀU = Σ⁻¹: the marginal as a prior factor.
	const Eigen::MatrixXd information = m.covariance.topLeftCorner(n, n).inverse();
	const Eigen::MatrixXd U = Eigen::LLT<Eigen::MatrixXd>(0.5 * (information + information.transpose())).matrixU();
	const std::vector<double> x(m.position.data(), m.position.data() + 3);
	smoother_.add_factor(std::make_shared<LinearPriorFactor>(U, Eigen::VectorXd::Zero(n), std::vector<std::vector<double>>{x},
															 std::vector<std::shared_ptr<const Manifold>>{manifold}),
						 {lm.var});
	return store_.add(std::move(lm));
}
}  // namespace swba::estimators::detail
