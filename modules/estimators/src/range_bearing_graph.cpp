#include "range_bearing_graph.h"

#include <swba/factors/between_pose.h>
#include <swba/factors/planar.h>
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
	// The re-linearised poses are re-solved at every step; the rest of the window W is the linear tail.
	return {o.window_size, o.relinearized_window(), o.first_estimate_jacobians, o.marginalization_threshold, o.solver};
}

/** The pose on the plane z = 0: (x, y, yaw). */
mrpt::poses::CPose3D planar_part(const mrpt::poses::CPose3D& p) { return {p.x(), p.y(), 0.0, p.yaw(), 0.0, 0.0}; }
/** A 2D sensor on the robot as MRPT's 2D EKF takes it (x, y, yaw), at its height z: its landmarks
 * lie on the plane of that height. */
mrpt::poses::CPose3D planar_sensor(const mrpt::poses::CPose3D& p) { return {p.x(), p.y(), p.z(), p.yaw(), 0.0, 0.0}; }

/** A factor on planar variables: `rows` of `f`, pose coordinates (ρx, ρy, ωz) for the variables
 * flagged in `is_pose`, (x, y) for the others. */
std::shared_ptr<Factor> planar(std::shared_ptr<const Factor> f, std::vector<int> rows, const std::vector<bool>& is_pose)
{
	std::vector<std::vector<int>> coords;
	for (bool pose : is_pose) coords.push_back(pose ? planar_pose_coordinates() : std::vector<int>{0, 1});
	return std::make_shared<SubspaceFactor>(std::move(f), std::move(rows), std::move(coords));
}
}  // namespace

static DataAssociation resolve_association(DataAssociation a, const io::RawlogStep& step)
{
	if (a != DataAssociation::Auto) return a;
	for (const auto& r : step.readings)
		if (r.landmark_id < 0) return DataAssociation::Jcbb;
	return DataAssociation::Ids;
}

RangeBearingGraph::RangeBearingGraph(const SlidingWindowOptions& options)
	: opt_(validated(options)), smoother_(smoother_options(opt_)), gate_on_entry_(opt_.gate_readings)
{
	if (opt_.model != PoseModel::Auto) initialise(opt_.model);
}

void RangeBearingGraph::initialise(PoseModel model)
{
	model_ = model;
	loss_ = opt_.reading_loss(reading_dof());
	robust_scale_sq_ = opt_.robust_scale_squared(reading_dof());
	gate_ = ReadingGate(model_, opt_.gate_threshold(reading_dof()));
	const VariableId v0 = add_pose_variable(mrpt::poses::CPose3D());
	poses_.push_back({0.0, v0, mrpt::poses::CPose3D()});
	step_of_[v0] = 0;
	smoother_.add_state(0.0, v0);
	if (opt_.gauge == GaugeMode::Fixed)
		smoother_.problem().set_constant(v0);
	else if (opt_.gauge == GaugeMode::Prior)
	{
		std::shared_ptr<Factor> f = std::make_shared<PosePriorFactor>(mrpt::poses::CPose3D());
		const int n = model_ == PoseModel::Planar ? 3 : 6;
		if (model_ == PoseModel::Planar) f = planar(f, planar_pose_coordinates(), {true});
		f->set_information(opt_.gauge_prior_weight * Eigen::MatrixXd::Identity(n, n));
		smoother_.add_factor(f, {v0});
	}
}

VariableId RangeBearingGraph::add_pose_variable(const mrpt::poses::CPose3D& pose)
{
	Problem& problem = smoother_.problem();
	if (model_ != PoseModel::Planar) return problem.add_pose(pose);
	double x[SE3Manifold::kAmbient];
	SE3Manifold::from_pose(planar_part(pose), x);
	return problem.add_variable(x, planar_pose_manifold(), Group::Kept);
}

mrpt::poses::CPose3D RangeBearingGraph::pose(VariableId var) const
{
	return SE3Manifold::to_pose(smoother_.problem().value(var));
}

bool RangeBearingGraph::is_world_point(VariableId v) const
{
	const Landmark* lm = store_.find_by_variable(v);
	return lm && (opt_.landmarks == LandmarkParameterization::Xyz || lm->world_xyz);
}

std::map<std::int32_t, Eigen::Vector3d> RangeBearingGraph::landmark_positions() const
{
	std::map<std::int32_t, Eigen::Vector3d> out;
	for (const auto& [id, lm] : store_) out[id] = world_position(lm);
	for (const auto& [id, m] : store_.map()) out[id] = m.position;  // never in the state as well
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
	return smoother_.add_factor(model_reading_factor(model_, f, gate_.reading_sigma(o)), vars, loss_);
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
	if (model_ == PoseModel::Planar)
	{
		// A point on the sensor's plane, held there: a world point from the start (no re-anchoring).
		x0 = inverse_depth_to_world(problem.value(poses_[k].var), poses_[k].sensor, lam);
		lm.world_xyz = true;
	}
	std::shared_ptr<const Manifold> manifold = euclidean_manifold(3);
	if (model_ == PoseModel::Planar) manifold = planar_point_manifold();
	lm.var = problem.add_variable(x0, std::move(manifold), Group::Eliminable);
	return store_.add(std::move(lm));
}

Eigen::MatrixXd RangeBearingGraph::add_odometry_factor(const io::RawlogStep& step, VariableId vprev, VariableId vnew)
{
	std::shared_ptr<Factor> odo = std::make_shared<BetweenPoseFactor>(step.odometry.mean);
	Eigen::MatrixXd information;
	if (model_ == PoseModel::Planar)
	{
		odo = planar(odo, planar_pose_coordinates(), {true, true});
		information = io::planar_odometry_information(step.odometry, opt_.odometry);
	}
	else
		information = io::odometry_information(step.odometry, opt_.odometry);
	odo->set_information(information);
	smoother_.add_factor(odo, {vprev, vnew});
	return information;
}

void RangeBearingGraph::add_step(const io::RawlogStep& step, StepSummary& sum)
{
	if (!step.has_odometry) throw std::invalid_argument("step " + std::to_string(step.index) + " has no odometry");
	if (model_ == PoseModel::Auto)
		initialise(step.odometry_is_2d && io::is_planar_step(step) ? PoseModel::Planar : PoseModel::Spatial);
	if (model_ == PoseModel::Planar && !io::is_planar_step(step))
		throw std::invalid_argument("step " + std::to_string(step.index) +
									": 3D odometry or a reading with pitch in a planar run (set the model to 6d)");
	const VariableId vprev = smoother_.states().back().var;
	const auto guess = pose_guesses_.find(step.time());
	const VariableId vnew =
		add_pose_variable(guess != pose_guesses_.end() ? guess->second : pose(vprev) + step.odometry.mean);
	if (step.has_observation) last_sensor_ = model_ == PoseModel::Planar ? planar_sensor(step.sensor_pose) : step.sensor_pose;
	poses_.push_back({step.time(), vnew, last_sensor_});
	const std::size_t k = poses_.size() - 1;
	step_of_[vnew] = k;
	smoother_.add_state(step.time(), vnew);
	const Eigen::MatrixXd odo_info = add_odometry_factor(step, vprev, vnew);
	if (step.readings.empty()) return;
	if (association_ == DataAssociation::Auto) association_ = resolve_association(opt_.association, step);
	const bool associating = association_ != DataAssociation::Ids;
	if (gate_on_entry_ || associating) gate_.set_prediction_covariance(odo_info.inverse());
	std::vector<std::pair<std::int32_t, Observation>> readings;
	for (const auto& rd : step.readings)
	{
		Eigen::Vector3d sigma;
		if (model_ == PoseModel::Planar)
			sigma << opt_.sensor.resolve_range_yaw(step, &rd), 0.0;
		else
			sigma = opt_.sensor.resolve(step, &rd);
		readings.push_back({rd.landmark_id, {k, {rd.range, rd.yaw, rd.pitch}, sigma, -1, readings.size()}});
	}
	assigned_ids_.resize(k + 1);
	std::vector<bool> matched(readings.size(), false);
	if (associating)
		associate_readings(readings, assigned_ids_[k], matched);
	else
		for (const auto& [id, o] : readings)
		{
			if (id < 0)
				throw std::invalid_argument("step " + std::to_string(step.index) +
											": a reading without a landmark ID (data association: nn or jcbb)");
			assigned_ids_[k].push_back(id);
		}
	if (opt_.policy == LandmarkPolicy::Map)
		for (const auto& [id, o] : readings)
			if (!store_.find(id) && store_.in_map(id))
			{
				restore_from_map(id);
				sum.landmarks_from_map++;
			}
	sum.readings += static_cast<int>(readings.size());
	counts_.readings += readings.size();
	admit_step_readings(readings, matched, sum);
	if (gate_on_entry_ && !associating) retest_held(k, sum);
}

void RangeBearingGraph::admit_step_readings(const std::vector<std::pair<std::int32_t, Observation>>& readings,
											const std::vector<bool>& matched, StepSummary& sum)
{
	if (gate_on_entry_) centre_gate(readings);
	for (std::size_t i = 0; i < readings.size(); i++)
	{
		const auto& [id, o] = readings[i];
		if (gate_on_entry_)
		{
			if (matched[i])
				admit_associated(id, o);
			else
				admit_reading(id, o, sum);
			continue;
		}
		Landmark* lm = store_.find(id);
		admit(lm ? *lm : add_landmark(id, o), o);
	}
}

smoother::PriorOnly RangeBearingGraph::prior_only(VariableId v) const
{
	if (!opt_.eliminate_prior_only_landmarks || !is_landmark(v)) return smoother::PriorOnly::Keep;
	// The SLAM policy's prior-only landmarks are kept as their conditional (exact, cost per step not
	// cubic in the map); data association asks for their covariances at every step, which the
	// per-solve elimination keeps available (doc/window.md, "Cost per step"). The association is
	// resolved at the first step with readings, before any landmark exists.
	return opt_.policy == LandmarkPolicy::Slam && association_ == DataAssociation::Ids ? smoother::PriorOnly::Store
																					  : smoother::PriorOnly::Eliminate;
}

void RangeBearingGraph::admit(Landmark& lm, Observation o)
{
	o.factor = add_observation_factor(lm, o);
	lm.obs.push_back(o);
}

bool RangeBearingGraph::forget_landmark(VariableId v)
{
	std::size_t held = 0;
	if (!store_.forget(v, held)) return false;
	counts_.excluded += held;
	return true;
}

void RangeBearingGraph::replace_landmark_variable(Landmark& lm, VariableId v)
{
	for (auto& o : lm.obs) smoother_.problem().remove_factor(o.factor);
	smoother_.problem().remove_variable(lm.var);
	store_.rebind(lm, v);
	for (auto& o : lm.obs) o.factor = add_observation_factor(lm, o);
}
}  // namespace swba::estimators::detail
