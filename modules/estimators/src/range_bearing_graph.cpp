#include "range_bearing_graph.h"

#include <swba/core/chi2.h>
#include <swba/factors/between_pose.h>
#include <swba/factors/pose_prior.h>

#include <Eigen/LU>

#include <algorithm>
#include <stdexcept>
#include <string>

namespace swba::estimators::detail
{
namespace
{
SlidingWindowOptions validated(const SlidingWindowOptions& options)
{
	options.validate();
	return options;
}

smoother::FixedLagSmootherOptions smoother_options(const SlidingWindowOptions& o)
{
	smoother::FixedLagSmootherOptions s;
	s.lag = o.window_size;
	s.first_estimate_jacobians = o.first_estimate_jacobians;
	s.marginalization_threshold = o.marginalization_threshold;
	s.eliminate_prior_only = o.eliminate_prior_only_landmarks;
	s.solver = o.solver;
	return s;
}
}  // namespace

RangeBearingGraph::RangeBearingGraph(const SlidingWindowOptions& options)
	: opt_(validated(options)),
	  smoother_(smoother_options(opt_)),
	  loss_(opt_.reading_loss()),
	  robust_scale_sq_(chi2_quantile(opt_.robust_probability, 3)),
	  gate_threshold_(opt_.gate_threshold()),
	  gate_on_entry_(opt_.gate_readings)
{
	Problem& problem = smoother_.problem();
	const VariableId v0 = problem.add_pose(mrpt::poses::CPose3D());
	poses_.push_back({0.0, v0, mrpt::poses::CPose3D()});
	step_of_[v0] = 0;
	smoother_.add_state(0.0, v0);
	if (opt_.gauge == GaugeMode::Fixed)
		problem.set_constant(v0);
	else if (opt_.gauge == GaugeMode::Prior)
	{
		auto f = std::make_shared<PosePriorFactor>(mrpt::poses::CPose3D());
		f->set_information(opt_.gauge_prior_weight * Eigen::MatrixXd::Identity(6, 6));
		smoother_.add_factor(f, {v0});
	}
}

bool RangeBearingGraph::is_world_point(VariableId v) const
{
	auto it = landmark_of_var_.find(v);
	return it != landmark_of_var_.end() &&
		(opt_.landmarks == LandmarkParameterization::Xyz || landmarks_.at(it->second).world_xyz);
}

std::map<std::int32_t, Eigen::Vector3d> RangeBearingGraph::landmark_positions() const
{
	std::map<std::int32_t, Eigen::Vector3d> out;
	for (const auto& [id, lm] : landmarks_) out[id] = world_position(lm);
	return out;
}

FactorId RangeBearingGraph::add_observation_factor(const Landmark& lm, const Observation& o)
{
	std::shared_ptr<Factor> f;
	std::vector<VariableId> vars;
	const auto& P = poses_[o.pose_step];
	if (opt_.landmarks == LandmarkParameterization::Xyz || lm.world_xyz)
	{
		f = std::make_shared<RangeBearingXyzFactor>(o.z, P.sensor);
		vars = {P.var, lm.var};
	}
	else if (o.pose_step == lm.anchor_step)
	{
		f = std::make_shared<RangeBearingInverseDepthAnchorFactor>(o.z);
		vars = {lm.var};
	}
	else
	{
		f = std::make_shared<RangeBearingInverseDepthFactor>(o.z, P.sensor, poses_[lm.anchor_step].sensor);
		vars = {poses_[lm.anchor_step].var, P.var, lm.var};
	}
	f->set_information(o.sigma.cwiseInverse().cwiseAbs2().asDiagonal().toDenseMatrix());
	return smoother_.add_factor(f, vars, loss_);
}

Landmark& RangeBearingGraph::add_landmark(std::int32_t id, const Observation& o)
{
	Problem& problem = smoother_.problem();
	const std::size_t k = o.pose_step;
	Landmark lm;
	lm.id = id;
	lm.anchor_step = k;
	Eigen::Vector3d x0;
	const Eigen::Vector3d lam = inverse_depth_from_measurement(o.z);
	if (opt_.landmarks == LandmarkParameterization::Xyz)
		x0 = inverse_depth_to_world(problem.value(poses_[k].var), poses_[k].sensor, lam);
	else
		x0 = lam;
	lm.var = problem.add_variable(x0, euclidean_manifold(3), Group::Eliminable);
	landmark_of_var_[lm.var] = lm.id;
	return landmarks_.emplace(lm.id, std::move(lm)).first->second;
}

void RangeBearingGraph::add_step(const io::RawlogStep& step, StepSummary& sum)
{
	if (!step.has_odometry) throw std::invalid_argument("step " + std::to_string(step.index) + " has no odometry");
	Problem& problem = smoother_.problem();
	const VariableId vprev = smoother_.states().back().var;
	const mrpt::poses::CPose3D pose_new = problem.pose(vprev) + step.odometry.mean;
	const VariableId vnew = problem.add_pose(pose_new);
	if (step.has_observation) last_sensor_ = step.sensor_pose;
	poses_.push_back({step.time(), vnew, step.has_observation ? step.sensor_pose : last_sensor_});
	const std::size_t k = poses_.size() - 1;
	step_of_[vnew] = k;
	smoother_.add_state(step.time(), vnew);
	auto odo = std::make_shared<BetweenPoseFactor>(step.odometry.mean);
	const Eigen::Matrix<double, 6, 6> odo_info = io::odometry_information(step.odometry, opt_.odometry);
	odo->set_information(odo_info);
	smoother_.add_factor(odo, {vprev, vnew});
	if (step.readings.empty()) return;
	if (gate_on_entry_) newest_pose_cov_ = odo_info.inverse();
	const Eigen::Vector3d sigma = opt_.sensor.resolve(step);
	for (const auto& rd : step.readings)
	{
		Observation o{k, {rd.range, rd.yaw, rd.pitch}, sigma, -1};
		sum.readings++;
		counts_.readings++;
		if (gate_on_entry_)
		{
			admit_reading(rd.landmark_id, o, sum);
			continue;
		}
		auto it = landmarks_.find(rd.landmark_id);
		admit(it == landmarks_.end() ? add_landmark(rd.landmark_id, o) : it->second, o);
	}
}

void RangeBearingGraph::admit(Landmark& lm, Observation o)
{
	o.factor = add_observation_factor(lm, o);
	lm.obs.push_back(o);
}

bool RangeBearingGraph::forget_landmark(VariableId v)
{
	auto it = landmark_of_var_.find(v);
	if (it == landmark_of_var_.end()) return false;
	const std::size_t held = landmarks_.at(it->second).held.size();
	counts_.excluded += held;
	landmarks_.erase(it->second);
	landmark_of_var_.erase(it);
	return true;
}

void RangeBearingGraph::forget_observations(const std::set<FactorId>& removed)
{
	for (auto& [id, lm] : landmarks_)
		lm.obs.erase(std::remove_if(lm.obs.begin(), lm.obs.end(),
									[&](const Observation& ob) { return removed.count(ob.factor) > 0; }),
					 lm.obs.end());
}

void RangeBearingGraph::replace_landmark_variable(Landmark& lm, VariableId v)
{
	for (auto& o : lm.obs) smoother_.problem().remove_factor(o.factor);
	landmark_of_var_.erase(lm.var);
	smoother_.remove_variable(lm.var);
	lm.var = v;
	landmark_of_var_[v] = lm.id;
	for (auto& o : lm.obs) o.factor = add_observation_factor(lm, o);
}
}  // namespace swba::estimators::detail
