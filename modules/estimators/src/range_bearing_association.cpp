// Data association of the range-bearing graph: readings without a landmark ID get one before they
// are gated (doc/association.md).
#include "range_bearing_graph.h"

#include <swba/core/chi2.h>

#include <mrpt/poses/CPoint3D.h>

#include <Eigen/Cholesky>

#include <algorithm>
#include <set>
#include <cmath>

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

/** The measurement of a point in the sensor frame (inverse of reading_point). */
RangeBearingMeasurement measurement_of(const Eigen::Vector3d& s)
{
	const double r = s.norm();
	static const double sign = reading_point({1.0, 0.0, 0.3}).z() > 0 ? 1.0 : -1.0;  // the pitch convention
	return {r, std::atan2(s.y(), s.x()), sign * std::asin(std::clamp(s.z() / std::max(r, 1e-12), -1.0, 1.0))};
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
										   std::vector<std::int32_t>& assigned)
{
	const int dim = model_ == PoseModel::Planar ? 2 : 3;
	const auto& P = poses_[readings.front().second.pose_step];
	const Manifold& M = *smoother_.problem().variable(P.var).manifold;
	const int dt = M.tangent_size();
	const double* x = smoother_.problem().value(P.var);
	// Candidates: the graph's landmarks (world position, readings averaged) and the first readings
	// still waiting for confirmation (provisional landmarks).
	struct Candidate
	{
		std::int32_t id;
		Eigen::Vector3d p;
		std::size_t n;     ///< readings its estimate averages
		std::size_t gap;   ///< steps since it was last seen (≥ 1)
	};
	const std::size_t k = readings.front().second.pose_step;
	std::vector<Candidate> cand;
	for (const auto& [id, lm] : landmarks_)
	{
		std::size_t last = lm.anchor_step;
		for (const auto& o : lm.obs) last = std::max(last, o.pose_step);
		for (const auto& o : lm.held) last = std::max(last, o.pose_step);
		cand.push_back({id, world_position(lm), std::max<std::size_t>(lm.obs.size(), 1), k > last ? k - last : 1});
	}
	for (const auto& [id, waiting] : unconfirmed_)
		for (const auto& o : waiting)
		{
			const auto& C = poses_[o.pose_step];
			cand.push_back({id,
							inverse_depth_to_world(smoother_.problem().value(C.var), C.sensor,
												   inverse_depth_from_measurement(o.z)),
							1, k > o.pose_step ? k - o.pose_step : 1});
		}
	AssociationProblem prob;
	prob.dim = dim;
	for (const auto& [id, o] : readings)
	{
		prob.readings.push_back(reading_point(o.z).head(dim));
		prob.reading_covariances.push_back(reading_point_covariance(o.z, o.sigma).topLeftCorner(dim, dim));
	}
	// A candidate's own uncertainty: its estimate's (≈ the reading noise at its predicted position over
	// its readings) and the pose's drift relative to it since it was last seen (≈ the odometry
	// covariance once per step of the gap beyond the newest, which all candidates share).
	const Eigen::Vector3d sigma = readings.front().second.sigma;
	const auto own_covariance = [&](std::size_t n_readings, std::size_t gap, const Eigen::Vector3d& s,
									const Eigen::MatrixXd& J) -> Eigen::MatrixXd {
		return reading_point_covariance(measurement_of(s), sigma).topLeftCorner(dim, dim) /
			static_cast<double>(n_readings) +
			static_cast<double>(gap - 1) * J * newest_pose_cov_ * J.transpose();
	};
	// Predictions in the new pose's sensor frame, with ∂s/∂pose (central differences on the tangent).
	std::vector<Eigen::MatrixXd> J_pose, jacobians;
	std::vector<Eigen::Vector3d> predicted;
	std::vector<std::vector<std::pair<double, int>>> compatible(prob.readings.size());
	std::vector<int> kept;
	std::vector<double> xp(M.ambient_size()), xm(M.ambient_size());
	const double gate = chi2_quantile(opt_.gate_probability, dim);
	for (std::size_t j = 0; j < cand.size(); j++)
	{
		const Eigen::Vector3d s = in_sensor_frame(x, P.sensor, cand[j].p);
		Eigen::MatrixXd J(dim, dt);
		for (int c = 0; c < dt; c++)
		{
			Eigen::VectorXd d = Eigen::VectorXd::Zero(dt);
			d[c] = 1e-6;
			M.plus(x, d.data(), xp.data());
			d[c] = -1e-6;
			M.plus(x, d.data(), xm.data());
			J.col(c) = ((in_sensor_frame(xp.data(), P.sensor, cand[j].p) - in_sensor_frame(xm.data(), P.sensor, cand[j].p)) /
						2e-6)
						   .head(dim);
		}
		const Eigen::MatrixXd Sj = J * newest_pose_cov_ * J.transpose() + own_covariance(cand[j].n, cand[j].gap, s, J);
		// Individually compatible readings (the others cannot choose this candidate).
		for (std::size_t i = 0; i < prob.readings.size(); i++)
		{
			const Eigen::VectorXd e = prob.readings[i] - s.head(dim);
			const double d2 = e.dot((Sj + prob.reading_covariances[i]).ldlt().solve(e));
			if (d2 <= gate) compatible[i].push_back({d2, static_cast<int>(j)});
		}
		predicted.push_back(s);
		jacobians.push_back(J);
	}
	// Each reading keeps its kMaxCandidates nearest compatible candidates: JCBB's search grows
	// exponentially with the choices per reading, and a farther candidate is never the nearest
	// neighbour and rarely the joint choice.
	constexpr std::size_t kMaxCandidates = 3;
	std::set<int> chosen;
	for (auto& c : compatible)
	{
		std::sort(c.begin(), c.end());
		for (std::size_t t = 0; t < std::min(kMaxCandidates, c.size()); t++) chosen.insert(c[t].second);
	}
	for (int j : chosen)
	{
		kept.push_back(j);
		prob.predictions.push_back(predicted[j].head(dim));
		J_pose.push_back(jacobians[j]);
	}
	const int n = static_cast<int>(kept.size());
	prob.prediction_covariance = Eigen::MatrixXd::Zero(n * dim, n * dim);
	for (int a = 0; a < n; a++)
		for (int b = 0; b < n; b++)
			prob.prediction_covariance.block(a * dim, b * dim, dim, dim) = J_pose[a] * newest_pose_cov_ * J_pose[b].transpose();
	for (int a = 0; a < n; a++)
	{
		const Candidate& c = cand[kept[a]];
		prob.prediction_covariance.block(a * dim, a * dim, dim, dim) +=
			own_covariance(c.n, c.gap, in_sensor_frame(x, P.sensor, c.p), J_pose[a]);
	}
	const std::vector<int> match = associate(prob, association_, opt_.gate_probability);
	assigned.clear();
	for (std::size_t i = 0; i < readings.size(); i++)
	{
		const std::int32_t id = match[i] >= 0 ? cand[kept[match[i]]].id : next_landmark_id_++;
		readings[i].first = id;
		assigned.push_back(id);
	}
}
}  // namespace swba::estimators::detail
