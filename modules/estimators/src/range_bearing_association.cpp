// Data association of the range-bearing graph: readings without a landmark ID get one before they
// are gated (doc/association.md).
#include "range_bearing_graph.h"

#include <swba/core/chi2.h>

#include <mrpt/poses/CPoint3D.h>

#include <Eigen/Cholesky>

#include <algorithm>
#include <map>
#include <set>
#include <stdexcept>
#include <string>

namespace swba::estimators::detail
{
namespace
{
/** A reading as a point in the sensor frame (the measurement model's inverse at the identity). */
Eigen::Vector3d reading_point(const RangeBearingMeasurement& z)
{
	return inverse_depth_to_world(mrpt::poses::CPose3D(), mrpt::poses::CPose3D(), inverse_depth_from_measurement(z));
}

/** Covariance of reading_point(z) for the noise σ = (range, yaw, pitch) (central differences). */
Eigen::Matrix3d reading_point_covariance(const RangeBearingMeasurement& z, const Eigen::Vector3d& sigma)
{
	Eigen::Matrix3d J;
	for (int c = 0; c < 3; c++)
	{
		const double h = 1e-6;
		RangeBearingMeasurement a = z, b = z;
		double* pa = c == 0 ? &a.range : c == 1 ? &a.yaw : &a.pitch;
		double* pb = c == 0 ? &b.range : c == 1 ? &b.yaw : &b.pitch;
		*pa += h;
		*pb -= h;
		J.col(c) = (reading_point(a) - reading_point(b)) / (2 * h);
	}
	return J * sigma.cwiseAbs2().asDiagonal() * J.transpose();
}

}  // namespace

Eigen::Vector3d RangeBearingGraph::in_sensor_frame(const double* pose_x, const mrpt::poses::CPose3D& sensor,
												  const Eigen::Vector3d& p) const
{
	const mrpt::poses::CPose3D s = SE3Manifold::to_pose(pose_x) + sensor;
	double lx, ly, lz;
	s.inverseComposePoint(p.x(), p.y(), p.z(), lx, ly, lz);
	return {lx, ly, lz};
}

void RangeBearingGraph::associate_readings(std::vector<std::pair<std::int32_t, Observation>>& readings,
										   std::vector<std::int32_t>& assigned, std::vector<bool>& matched)
{
	const int dim = model_ == PoseModel::Planar ? 2 : 3;
	Problem& problem = smoother_.problem();
	const std::size_t k = readings.front().second.pose_step;
	const PoseRecord& P = poses_[k];
	// Candidates: the graph's landmarks and the first readings still waiting for confirmation
	// (provisional landmarks: a world point from one reading at a window pose).
	struct Candidate
	{
		std::int32_t id;
		const Landmark* lm;          ///< a graph landmark, or null
		const Observation* first;    ///< a provisional landmark's reading, or null
		std::vector<VariableId> vars;  ///< the variables its world point depends on
	};
	std::vector<Candidate> cand;
	for (const auto& [id, lm] : landmarks_)
	{
		const bool world = opt_.landmarks == LandmarkParameterization::Xyz || lm.world_xyz || model_ == PoseModel::Planar;
		cand.push_back({id, &lm, nullptr, world ? std::vector<VariableId>{lm.var}
												: std::vector<VariableId>{lm.var, poses_[lm.anchor_step].var}});
	}
	for (const auto& [id, waiting] : unconfirmed_)
		for (const auto& o : waiting) cand.push_back({id, nullptr, &o, {poses_[o.pose_step].var}});
	// The candidate's prediction in the new pose's sensor frame, with variable `v` at `xv` (v < 0: all
	// at their current values; the new pose at its dead-reckoned value).
	const auto predict = [&](const Candidate& c, VariableId v, const double* xv) -> Eigen::Vector3d {
		const auto value = [&](VariableId u) { return u == v ? xv : problem.value(u); };
		Eigen::Vector3d p;
		if (c.lm && c.vars.size() == 1)
			p = Eigen::Map<const Eigen::Vector3d>(value(c.lm->var));
		else if (c.lm)
		{
			const PoseRecord& a = poses_[c.lm->anchor_step];
			p = inverse_depth_to_world(value(a.var), a.sensor, Eigen::Map<const Eigen::Vector3d>(value(c.lm->var)));
		}
		else
		{
			const PoseRecord& C = poses_[c.first->pose_step];
			p = inverse_depth_to_world(value(C.var), C.sensor, inverse_depth_from_measurement(c.first->z));
		}
		return in_sensor_frame(value(P.var), P.sensor, p);
	};
	// The joint covariance of the new pose and every variable a candidate depends on, from the
	// window's information at the current estimate: the new pose's marginal is the prediction of its
	// odometry from the previous estimate, and the cross-covariances say how a pose error moves the
	// landmarks seen with it (the gap since a landmark was last seen, the heading's lever arm).
	std::vector<VariableId> group{P.var};
	std::map<VariableId, int> at{{P.var, 0}};
	int D = problem.variable(P.var).manifold->tangent_size();
	for (const auto& c : cand)
		for (VariableId v : c.vars)
			if (at.emplace(v, D).second)
			{
				group.push_back(v);
				D += problem.variable(v).manifold->tangent_size();
			}
	CovarianceRequest request;
	request.groups.push_back(group);
	const CovarianceResult cov = covariances(request);
	if (!cov.ok)
		throw std::runtime_error("data association at step " + std::to_string(k) +
								 ": the window's covariance cannot be recovered (" + cov.message + ")");
	const Eigen::MatrixXd& Sigma = cov.blocks.front();
	// Predictions and their Jacobians on the group's tangent (central differences).
	const int n = static_cast<int>(cand.size());
	std::vector<Eigen::Vector3d> predicted(cand.size());
	Eigen::MatrixXd J = Eigen::MatrixXd::Zero(n * dim, D);
	std::vector<double> xp, xm;
	for (int j = 0; j < n; j++)
	{
		const Candidate& c = cand[static_cast<std::size_t>(j)];
		predicted[static_cast<std::size_t>(j)] = predict(c, -1, nullptr);
		std::vector<VariableId> vars{P.var};
		vars.insert(vars.end(), c.vars.begin(), c.vars.end());
		for (VariableId v : vars)
		{
			const Manifold& M = *problem.variable(v).manifold;
			const double* x = problem.value(v);
			xp.resize(static_cast<std::size_t>(M.ambient_size()));
			xm.resize(xp.size());
			for (int t = 0; t < M.tangent_size(); t++)
			{
				Eigen::VectorXd d = Eigen::VectorXd::Zero(M.tangent_size());
				d[t] = 1e-6;
				M.plus(x, d.data(), xp.data());
				d[t] = -1e-6;
				M.plus(x, d.data(), xm.data());
				J.block(j * dim, at.at(v) + t, dim, 1) =
					((predict(c, v, xp.data()) - predict(c, v, xm.data())) / 2e-6).head(dim);
			}
		}
	}
	// A provisional landmark's own noise: its reading's, turned from its pose's sensor frame into the
	// new one (the reading is not a variable of the window).
	const auto own_covariance = [&](const Candidate& c) -> Eigen::MatrixXd {
		if (!c.first) return Eigen::MatrixXd::Zero(dim, dim);
		const PoseRecord& C = poses_[c.first->pose_step];
		const mrpt::poses::CPose3D sc = SE3Manifold::to_pose(problem.value(C.var)) + C.sensor;
		const mrpt::poses::CPose3D sn = SE3Manifold::to_pose(problem.value(P.var)) + P.sensor;
		const Eigen::Matrix3d R = sn.getRotationMatrix().asEigen().transpose() * sc.getRotationMatrix().asEigen();
		return (R * reading_point_covariance(c.first->z, c.first->sigma) * R.transpose()).topLeftCorner(dim, dim);
	};
	AssociationProblem prob;
	prob.dim = dim;
	for (const auto& [id, o] : readings)
	{
		prob.readings.push_back(reading_point(o.z).head(dim));
		prob.reading_covariances.push_back(reading_point_covariance(o.z, o.sigma).topLeftCorner(dim, dim));
	}
	// Individually compatible readings of each candidate; each reading keeps its kMaxCandidates
	// nearest: JCBB's search grows exponentially with the choices per reading, and a farther candidate
	// is never the nearest neighbour and rarely the joint choice.
	const double gate = chi2_quantile(opt_.gate_probability, dim);
	std::vector<std::vector<std::pair<double, int>>> compatible(prob.readings.size());
	std::vector<Eigen::MatrixXd> own(cand.size());
	for (int j = 0; j < n; j++)
	{
		own[static_cast<std::size_t>(j)] = own_covariance(cand[static_cast<std::size_t>(j)]);
		const auto Jj = J.middleRows(j * dim, dim);
		const Eigen::MatrixXd Sj = Jj * Sigma * Jj.transpose() + own[static_cast<std::size_t>(j)];
		for (std::size_t i = 0; i < prob.readings.size(); i++)
		{
			const Eigen::VectorXd e = prob.readings[i] - predicted[static_cast<std::size_t>(j)].head(dim);
			const double d2 = e.dot((Sj + prob.reading_covariances[i]).ldlt().solve(e));
			if (d2 <= gate) compatible[i].push_back({d2, j});
		}
	}
	constexpr std::size_t kMaxCandidates = 3;
	std::set<int> chosen;
	for (auto& c : compatible)
	{
		std::sort(c.begin(), c.end());
		for (std::size_t t = 0; t < std::min(kMaxCandidates, c.size()); t++) chosen.insert(c[t].second);
	}
	const std::vector<int> kept(chosen.begin(), chosen.end());
	const int m = static_cast<int>(kept.size());
	Eigen::MatrixXd Jk(m * dim, D);
	for (int a = 0; a < m; a++)
	{
		Jk.middleRows(a * dim, dim) = J.middleRows(kept[static_cast<std::size_t>(a)] * dim, dim);
		prob.predictions.push_back(predicted[static_cast<std::size_t>(kept[static_cast<std::size_t>(a)])].head(dim));
	}
	prob.prediction_covariance = Jk * Sigma * Jk.transpose();
	for (int a = 0; a < m; a++)
		prob.prediction_covariance.block(a * dim, a * dim, dim, dim) += own[static_cast<std::size_t>(kept[static_cast<std::size_t>(a)])];
	const std::vector<int> match = associate(prob, association_, opt_.gate_probability);
	assigned.clear();
	matched.assign(readings.size(), false);
	for (std::size_t i = 0; i < readings.size(); i++)
	{
		matched[i] = match[i] >= 0;
		const std::int32_t id = match[i] >= 0 ? cand[static_cast<std::size_t>(kept[static_cast<std::size_t>(match[i])])].id
											  : next_landmark_id_++;
		readings[i].first = id;
		assigned.push_back(id);
	}
}
}  // namespace swba::estimators::detail
