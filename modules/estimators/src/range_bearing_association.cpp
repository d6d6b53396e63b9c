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
#include <vector>

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

/** Squared Mahalanobis distance of a reading (point `z`, covariance `R`, both reading_dof-sized) from a
 * prediction (point `y`, its block `S` of the predictions' joint covariance). */
double mahalanobis(const Eigen::VectorXd& z, const Eigen::MatrixXd& R, const Eigen::Vector3d& y, const Eigen::MatrixXd& S)
{
	const Eigen::VectorXd e = z - y.head(z.size());
	return e.dot((S + R).ldlt().solve(e));
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

std::vector<VariableId> RangeBearingGraph::target_variables(const PredictionTarget& t) const
{
	if (t.map) return {};
	if (!t.lm) return {poses_[t.first->pose_step].var};
	if (is_world_point(t.lm->var)) return {t.lm->var};
	return {t.lm->var, poses_[t.lm->anchor_step].var};
}

Eigen::Vector3d RangeBearingGraph::predict_target(std::size_t k, const PredictionTarget& t, VariableId v,
												  const double* xv) const
{
	const Problem& problem = smoother_.problem();
	const auto value = [&](VariableId u) { return u == v ? xv : problem.value(u); };
	Eigen::Vector3d p;
	if (t.map)
		p = t.map->position;
	else if (t.lm && is_world_point(t.lm->var))
		p = Eigen::Map<const Eigen::Vector3d>(value(t.lm->var));
	else if (t.lm)
	{
		const PoseRecord& a = poses_[t.lm->anchor_step];
		p = inverse_depth_to_world(value(a.var), a.sensor, Eigen::Map<const Eigen::Vector3d>(value(t.lm->var)));
	}
	else
	{
		const PoseRecord& C = poses_[t.first->pose_step];
		p = inverse_depth_to_world(value(C.var), C.sensor, inverse_depth_from_measurement(t.first->z));
	}
	const PoseRecord& P = poses_[k];
	return in_sensor_frame(value(P.var), P.sensor, p);
}

mrpt::poses::CPose3D RangeBearingGraph::sensor_in_world(std::size_t k) const
{
	return SE3Manifold::to_pose(smoother_.problem().value(poses_[k].var)) + poses_[k].sensor;
}

Eigen::MatrixXd RangeBearingGraph::provisional_noise(std::size_t k, const Observation& first) const
{
	const Eigen::Matrix3d R = sensor_in_world(k).getRotationMatrix().asEigen().transpose() *
							  sensor_in_world(first.pose_step).getRotationMatrix().asEigen();
	const int dim = reading_dof();
	return (R * reading_point_covariance(first.z, first.sigma) * R.transpose()).topLeftCorner(dim, dim);
}

Eigen::MatrixXd RangeBearingGraph::map_noise(std::size_t k, const MapLandmark& m) const
{
	const Eigen::Matrix3d R = sensor_in_world(k).getRotationMatrix().asEigen().transpose();
	const int dim = reading_dof();
	return (R * m.covariance * R.transpose()).topLeftCorner(dim, dim);
}

RangeBearingGraph::JointPrediction RangeBearingGraph::predict_jointly(std::size_t k,
																	  const std::vector<PredictionTarget>& targets)
{
	const int dim = reading_dof();
	const Problem& problem = smoother_.problem();
	const VariableId pose = poses_[k].var;
	// The joint covariance of the new pose and every variable a target depends on, from the window's
	// information at the current estimate: the new pose's marginal is the prediction of its odometry
	// from the previous estimate, and the cross-covariances say how a pose error moves the landmarks
	// seen with it (the drift since a landmark was last seen, with the heading's lever arm).
	std::vector<VariableId> group{pose};
	std::map<VariableId, int> at{{pose, 0}};
	int D = problem.variable(pose).manifold->tangent_size();
	std::vector<std::vector<VariableId>> vars;
	for (const auto& t : targets)
	{
		vars.push_back(target_variables(t));
		for (VariableId v : vars.back())
			if (at.emplace(v, D).second)
			{
				group.push_back(v);
				D += problem.variable(v).manifold->tangent_size();
			}
	}
	CovarianceRequest request;
	request.groups.push_back(group);
	const CovarianceResult cov = covariances(request);
	JointPrediction out;
	if (!cov.ok)
	{
		out.message = cov.message;
		return out;
	}
	out.ok = true;
	out.covariance = cov.blocks.front();
	// Predictions and their Jacobians on the group's tangent (central differences); a provisional
	// landmark's own noise: its reading's, turned from its pose's sensor frame into the new one (the
	// reading is not a variable of the window).
	const int n = static_cast<int>(targets.size());
	out.points.resize(targets.size());
	out.jacobian = Eigen::MatrixXd::Zero(n * dim, D);
	out.own.assign(targets.size(), Eigen::MatrixXd::Zero(dim, dim));
	out.support.resize(targets.size());
	for (int j = 0; j < n; j++) predict_one(k, targets[static_cast<std::size_t>(j)], vars[static_cast<std::size_t>(j)], at, j, out);
	return out;
}

void RangeBearingGraph::predict_one(std::size_t k, const PredictionTarget& t, const std::vector<VariableId>& vars,
									const std::map<VariableId, int>& at, int j, JointPrediction& out) const
{
	const int dim = reading_dof();
	const auto tj = static_cast<std::size_t>(j);
	out.points[tj] = predict_target(k, t, -1, nullptr);
	if (t.first) out.own[tj] = provisional_noise(k, *t.first);
	if (t.map) out.own[tj] = map_noise(k, *t.map);
	std::vector<VariableId> with_pose{poses_[k].var};
	with_pose.insert(with_pose.end(), vars.begin(), vars.end());
	std::sort(with_pose.begin(), with_pose.end());
	with_pose.erase(std::unique(with_pose.begin(), with_pose.end()), with_pose.end());
	for (VariableId v : with_pose)
	{
		const int nv = smoother_.problem().variable(v).manifold->tangent_size();
		out.support[tj].emplace_back(at.at(v), nv);
		target_jacobian(k, t, v, out.jacobian.block(j * dim, at.at(v), dim, nv));
	}
}

void RangeBearingGraph::target_jacobian(std::size_t k, const PredictionTarget& t, VariableId v,
										Eigen::Ref<Eigen::MatrixXd> J) const
{
	const Manifold& M = *smoother_.problem().variable(v).manifold;
	const double* x = smoother_.problem().value(v);
	std::vector<double> xp(static_cast<std::size_t>(M.ambient_size())), xm(xp.size());
	for (int c = 0; c < M.tangent_size(); c++)
	{
		Eigen::VectorXd d = Eigen::VectorXd::Zero(M.tangent_size());
		d[c] = 1e-6;
		M.plus(x, d.data(), xp.data());
		d[c] = -1e-6;
		M.plus(x, d.data(), xm.data());
		J.col(c) = ((predict_target(k, t, v, xp.data()) - predict_target(k, t, v, xm.data())) / 2e-6).head(J.rows());
	}
}

Eigen::MatrixXd RangeBearingGraph::JointPrediction::covariance_of(int a, int b, int dim) const
{
	Eigen::MatrixXd S = Eigen::MatrixXd::Zero(dim, dim);
	for (const auto& [ca, na] : support[static_cast<std::size_t>(a)])
		for (const auto& [cb, nb] : support[static_cast<std::size_t>(b)])
			S.noalias() += jacobian.block(a * dim, ca, dim, na) * covariance.block(ca, cb, na, nb) *
						   jacobian.block(b * dim, cb, dim, nb).transpose();
	if (a == b) S += own[static_cast<std::size_t>(a)];
	return S;
}

void RangeBearingGraph::retest_held(std::size_t k, StepSummary& sum)
{
	std::vector<PredictionTarget> targets;
	std::vector<Landmark*> holding;
	for (auto& [id, lm] : store_)
		for (const auto& h : lm.held)
			if (h.pose_step == k)
			{
				targets.push_back({&lm, nullptr});
				holding.push_back(&lm);
				break;
			}
	if (targets.empty()) return;
	const JointPrediction pred = predict_jointly(k, targets);
	if (!pred.ok) return;  // they stay held (counted), re-tested after the solve
	const int dim = reading_dof();
	for (std::size_t j = 0; j < holding.size(); j++)
	{
		Landmark& lm = *holding[j];
		const Eigen::MatrixXd S = pred.covariance_of(static_cast<int>(j), static_cast<int>(j), dim);
		std::vector<Observation> still;
		for (const auto& h : lm.held)
		{
			if (h.pose_step == k &&
				mahalanobis(reading_point(h.z).head(dim), reading_point_covariance(h.z, h.sigma).topLeftCorner(dim, dim),
							pred.points[j], S) <= gate_.threshold())
			{
				admit(lm, h);
				sum.gated--;
				counts_.gated--;
			}
			else
				still.push_back(h);
		}
		lm.held = std::move(still);
	}
}

void RangeBearingGraph::associate_readings(std::vector<std::pair<std::int32_t, Observation>>& readings,
										   std::vector<std::int32_t>& assigned, std::vector<bool>& matched)
{
	const int dim = reading_dof();
	const std::size_t k = readings.front().second.pose_step;
	std::vector<std::int32_t> ids;
	const std::vector<PredictionTarget> cand = association_candidates(ids);
	const JointPrediction pred = predict_jointly(k, cand);
	if (!pred.ok)
		throw std::runtime_error("data association at step " + std::to_string(k) +
								 ": the window's covariance cannot be recovered (" + pred.message + ")");
	AssociationProblem prob;
	prob.dim = dim;
	for (const auto& [id, o] : readings)
	{
		prob.readings.push_back(reading_point(o.z).head(dim));
		prob.reading_covariances.push_back(reading_point_covariance(o.z, o.sigma).topLeftCorner(dim, dim));
	}
	const std::vector<int> kept =
		compatible_candidates(prob, pred, cand.size(), chi2_quantile(opt_.gate_probability, dim));
	const int m = static_cast<int>(kept.size());
	prob.prediction_covariance = Eigen::MatrixXd::Zero(m * dim, m * dim);
	for (int a = 0; a < m; a++)
	{
		const int ja = kept[static_cast<std::size_t>(a)];
		prob.predictions.push_back(pred.points[static_cast<std::size_t>(ja)].head(dim));
		for (int b = 0; b < m; b++)
			prob.prediction_covariance.block(a * dim, b * dim, dim, dim) =
				pred.covariance_of(ja, kept[static_cast<std::size_t>(b)], dim);
	}
	const std::vector<int> match = associate(prob, association_, opt_.gate_probability);
	assigned.clear();
	matched.assign(readings.size(), false);
	for (std::size_t i = 0; i < readings.size(); i++)
	{
		matched[i] = match[i] >= 0;
		const std::int32_t id =
			matched[i] ? ids[static_cast<std::size_t>(kept[static_cast<std::size_t>(match[i])])] : next_landmark_id_++;
		readings[i].first = id;
		assigned.push_back(id);
	}
}
std::vector<RangeBearingGraph::PredictionTarget> RangeBearingGraph::association_candidates(
	std::vector<std::int32_t>& ids) const
{
	// The graph's landmarks, the first readings still waiting for confirmation (provisional landmarks:
	// a world point from one reading at a window pose) and the map's landmarks (map policy: their
	// marginals, independent of the window, as the map keeps them).
	std::vector<PredictionTarget> cand;
	for (const auto& [id, lm] : store_)
	{
		ids.push_back(id);
		cand.push_back({&lm, nullptr});
	}
	for (const auto& [id, waiting] : store_.unconfirmed())
		for (const auto& o : waiting)
		{
			ids.push_back(id);
			cand.push_back({nullptr, &o});
		}
	for (const auto& [id, m] : store_.map())
	{
		ids.push_back(id);
		cand.push_back({nullptr, nullptr, &m});
	}
	return cand;
}

std::vector<int> RangeBearingGraph::compatible_candidates(const AssociationProblem& prob, const JointPrediction& pred,
														  std::size_t num_candidates, double gate)
{
	// Individually compatible readings of each candidate; each reading keeps its kMaxCandidates
	// nearest: JCBB's search grows exponentially with the choices per reading, and a farther candidate
	// is never the nearest neighbour and rarely the joint choice.
	const int dim = prob.dim;
	std::vector<std::vector<std::pair<double, int>>> compatible(prob.readings.size());
	for (int j = 0; j < static_cast<int>(num_candidates); j++)
	{
		const Eigen::MatrixXd S = pred.covariance_of(j, j, dim);
		for (std::size_t i = 0; i < prob.readings.size(); i++)
		{
			const double d2 =
				mahalanobis(prob.readings[i], prob.reading_covariances[i], pred.points[static_cast<std::size_t>(j)], S);
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
	return std::vector<int>(chosen.begin(), chosen.end());
}
}  // namespace swba::estimators::detail
