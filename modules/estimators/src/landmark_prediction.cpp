#include "landmark_prediction.h"

#include <swba/core/chi2.h>
#include <swba/core/manifold.h>

#include <Eigen/Cholesky>

#include <algorithm>
#include <set>

namespace swba::estimators::detail
{
namespace
{
/** World point `p` in the frame of `sensor` on the robot at `pose_x`. */
Eigen::Vector3d in_sensor_frame(const double* pose_x, const mrpt::poses::CPose3D& sensor, const Eigen::Vector3d& p)
{
	const mrpt::poses::CPose3D s = SE3Manifold::to_pose(pose_x) + sensor;
	double lx, ly, lz;
	s.inverseComposePoint(p.x(), p.y(), p.z(), lx, ly, lz);
	return {lx, ly, lz};
}
/** Per reading of `prob`, the candidates individually compatible with it (inside `gate`), nearest
 * first. */
std::vector<std::vector<std::pair<double, int>>> individually_compatible(const AssociationProblem& prob,
																		 const JointPrediction& pred,
																		 std::size_t num_candidates, double gate)
{
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
	for (auto& c : compatible) std::sort(c.begin(), c.end());
	return compatible;
}

/** The candidates that enter the association problem, in increasing order: each reading's few
 * nearest compatible ones. JCBB's search grows exponentially with the choices per reading, and a
 * farther candidate is never the nearest neighbour and rarely the joint choice. */
std::vector<int> kept_candidates(const std::vector<std::vector<std::pair<double, int>>>& compatible)
{
	constexpr std::size_t kMaxCandidates = 3;
	std::set<int> chosen;
	for (const auto& c : compatible)
		for (std::size_t t = 0; t < std::min(kMaxCandidates, c.size()); t++) chosen.insert(c[t].second);
	return std::vector<int>(chosen.begin(), chosen.end());
}
}  // namespace

Eigen::Vector3d reading_point(const RangeBearingMeasurement& z)
{
	return inverse_depth_to_world(mrpt::poses::CPose3D(), mrpt::poses::CPose3D(), inverse_depth_from_measurement(z));
}

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

double mahalanobis(const Eigen::VectorXd& z, const Eigen::MatrixXd& R, const Eigen::Vector3d& y, const Eigen::MatrixXd& S)
{
	const Eigen::VectorXd e = z - y.head(z.size());
	return e.dot((S + R).ldlt().solve(e));
}

std::vector<VariableId> LandmarkPredictor::target_variables(const PredictionTarget& t) const
{
	if (t.map) return {};
	if (!t.lm) return {poses_[t.first->pose_step].var};
	if (is_world_point(*t.lm)) return {t.lm->var};
	return {t.lm->var, poses_[t.lm->anchor_step].var};
}

Eigen::Vector3d LandmarkPredictor::predict_target(std::size_t k, const PredictionTarget& t, VariableId v,
												  const double* xv) const
{
	const auto value = [&](VariableId u) { return u == v ? xv : problem_.value(u); };
	Eigen::Vector3d p;
	if (t.map)
		p = t.map->position;
	else if (t.lm && is_world_point(*t.lm))
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

mrpt::poses::CPose3D LandmarkPredictor::sensor_in_world(std::size_t k) const
{
	return SE3Manifold::to_pose(problem_.value(poses_[k].var)) + poses_[k].sensor;
}

Eigen::MatrixXd LandmarkPredictor::provisional_noise(std::size_t k, const Observation& first) const
{
	const Eigen::Matrix3d R = sensor_in_world(k).getRotationMatrix().asEigen().transpose() *
							  sensor_in_world(first.pose_step).getRotationMatrix().asEigen();
	const int dim = reading_dof();
	return (R * reading_point_covariance(first.z, first.sigma) * R.transpose()).topLeftCorner(dim, dim);
}

Eigen::MatrixXd LandmarkPredictor::map_noise(std::size_t k, const MapLandmark& m) const
{
	const Eigen::Matrix3d R = sensor_in_world(k).getRotationMatrix().asEigen().transpose();
	const int dim = reading_dof();
	return (R * m.covariance * R.transpose()).topLeftCorner(dim, dim);
}

LandmarkPredictor::Group LandmarkPredictor::group(std::size_t k, const std::vector<PredictionTarget>& targets) const
{
	// The joint covariance of the new pose and every variable a target depends on, from the window's
	// information at the current estimate: the new pose's marginal is the prediction of its odometry
	// from the previous estimate, and the cross-covariances say how a pose error moves the landmarks
	// seen with it (the drift since a landmark was last seen, with the heading's lever arm).
	const VariableId pose = poses_[k].var;
	Group g;
	g.vars.push_back(pose);
	g.at.emplace(pose, 0);
	g.dim = problem_.variable(pose).manifold->tangent_size();
	for (const auto& t : targets)
	{
		g.of_target.push_back(target_variables(t));
		for (VariableId v : g.of_target.back())
			if (g.at.emplace(v, g.dim).second)
			{
				g.vars.push_back(v);
				g.dim += problem_.variable(v).manifold->tangent_size();
			}
	}
	return g;
}

JointPrediction LandmarkPredictor::predict(std::size_t k, const std::vector<PredictionTarget>& targets, const Group& g,
										   const CovarianceResult& cov) const
{
	const int dim = reading_dof();
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
	out.jacobian = Eigen::MatrixXd::Zero(n * dim, g.dim);
	out.own.assign(targets.size(), Eigen::MatrixXd::Zero(dim, dim));
	out.support.resize(targets.size());
	for (int j = 0; j < n; j++) predict_one(k, targets[static_cast<std::size_t>(j)], g, j, out);
	return out;
}

void LandmarkPredictor::predict_one(std::size_t k, const PredictionTarget& t, const Group& g, int j,
									JointPrediction& out) const
{
	const int dim = reading_dof();
	const auto tj = static_cast<std::size_t>(j);
	out.points[tj] = predict_target(k, t, -1, nullptr);
	if (t.first) out.own[tj] = provisional_noise(k, *t.first);
	if (t.map) out.own[tj] = map_noise(k, *t.map);
	const std::vector<VariableId>& vars = g.of_target[tj];
	std::vector<VariableId> with_pose{poses_[k].var};
	with_pose.insert(with_pose.end(), vars.begin(), vars.end());
	std::sort(with_pose.begin(), with_pose.end());
	with_pose.erase(std::unique(with_pose.begin(), with_pose.end()), with_pose.end());
	for (VariableId v : with_pose)
	{
		const int nv = problem_.variable(v).manifold->tangent_size();
		out.support[tj].emplace_back(g.at.at(v), nv);
		target_jacobian(k, t, v, out.jacobian.block(j * dim, g.at.at(v), dim, nv));
	}
}

void LandmarkPredictor::target_jacobian(std::size_t k, const PredictionTarget& t, VariableId v,
										Eigen::Ref<Eigen::MatrixXd> J) const
{
	const Manifold& M = *problem_.variable(v).manifold;
	const double* x = problem_.value(v);
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

JointPrediction with_pose_covariance_scaled(JointPrediction pred, int pose_dim, double factor)
{
	pred.covariance.topLeftCorner(pose_dim, pose_dim) *= factor;
	return pred;
}

Eigen::MatrixXd JointPrediction::covariance_of(int a, int b, int dim) const
{
	Eigen::MatrixXd S = Eigen::MatrixXd::Zero(dim, dim);
	for (const auto& [ca, na] : support[static_cast<std::size_t>(a)])
		for (const auto& [cb, nb] : support[static_cast<std::size_t>(b)])
			S.noalias() += jacobian.block(a * dim, ca, dim, na) * covariance.block(ca, cb, na, nb) *
						   jacobian.block(b * dim, cb, dim, nb).transpose();
	if (a == b) S += own[static_cast<std::size_t>(a)];
	return S;
}

ReadingMatch match_readings(const std::vector<std::pair<std::int32_t, Observation>>& readings,
							const JointPrediction& pred, std::size_t num_candidates, DataAssociation method,
							double probability, int dim)
{
	AssociationProblem prob;
	prob.dim = dim;
	for (const auto& [id, o] : readings)
	{
		prob.readings.push_back(reading_point(o.z).head(dim));
		prob.reading_covariances.push_back(reading_point_covariance(o.z, o.sigma).topLeftCorner(dim, dim));
	}
	ReadingMatch out;
	const auto compatible = individually_compatible(prob, pred, num_candidates, chi2_quantile(probability, dim));
	for (const auto& c : compatible)
	{
		out.compatible.emplace_back();
		for (const auto& [d2, j] : c) out.compatible.back().push_back(j);
	}
	const std::vector<int> kept = kept_candidates(compatible);
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
	out.target = associate(prob, method, probability, &out.search_cut);
	for (int& j : out.target)
		if (j >= 0) j = kept[static_cast<std::size_t>(j)];
	return out;
}
}  // namespace swba::estimators::detail
