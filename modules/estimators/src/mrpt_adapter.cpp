#include <swba/estimators/mrpt_adapter.h>

#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CActionRobotMovement3D.h>

#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>

namespace swba::estimators
{
namespace
{
using mrpt::obs::CActionCollection;
using mrpt::obs::CObservationBearingRange;
using mrpt::obs::CSensoryFrame;

bool finite_pose(const mrpt::poses::CPose3D& p)
{
	for (int i = 0; i < 6; i++)
		if (!std::isfinite(p[i])) return false;
	return true;
}

// The same rules as io::read_rawlog's reader (modules/io/src/rawlog.cpp), which has no public
// per-step entry point: keep both in step (the install test compares the two paths end to end).
bool valid_reading(const CObservationBearingRange::TMeasurement& m, bool require_ids)
{
	return std::isfinite(m.range) && m.range > 0 && std::isfinite(m.yaw) && std::isfinite(m.pitch) &&
		!(require_ids && m.landmarkID < 0);
}
}  // namespace

io::RawlogStep MrptStepConverter::convert(const CActionCollection::Ptr& actions, const CSensoryFrame::Ptr& observations)
{
	const std::string at = "step " + std::to_string(steps_);
	auto fail = [&](const std::string& msg) { throw std::invalid_argument(at + ": " + msg); };
	if (!actions) fail("null action collection");
	if (!observations) fail("null sensory frame");

	io::RawlogStep s;
	s.index = steps_;
	s.actions = actions;
	s.observations = observations;

	s.has_odometry = actions->getFirstMovementEstimation(s.odometry);
	if (s.has_odometry)
	{
		s.odometry_is_2d = !actions->getActionByClass<mrpt::obs::CActionRobotMovement3D>() &&
			actions->getActionByClass<mrpt::obs::CActionRobotMovement2D>();
		if (!finite_pose(s.odometry.mean)) fail("odometry mean is not finite");
		for (int i = 0; i < 6; i++)
		{
			for (int j = 0; j < 6; j++)
				if (!std::isfinite(s.odometry.cov(i, j))) fail("odometry covariance is not finite");
			if (s.odometry.cov(i, i) < 0) fail("odometry covariance has a negative variance");
		}
	}
	else
	{
		s.odometry = mrpt::poses::CPose3DPDFGaussian();
		s.odometry.cov.setZero();
	}

	bool any_skipped = false;
	std::vector<std::vector<CObservationBearingRange::TMeasurement>> kept_per_obs;
	for (const auto& o : *observations)
	{
		if (!o || !IS_CLASS(*o, CObservationBearingRange)) continue;
		const auto& br = dynamic_cast<const CObservationBearingRange&>(*o);
		const double stds[3] = {br.sensor_std_range, br.sensor_std_yaw, br.sensor_std_pitch};
		if (!finite_pose(br.sensorLocationOnRobot)) fail("sensorLocationOnRobot is not finite");
		for (double v : stds)
			if (!std::isfinite(v) || v < 0) fail("sensor_std_range/yaw/pitch must be finite and >= 0");
		if (!s.has_observation)
		{
			s.has_observation = true;
			s.sensor_pose = br.sensorLocationOnRobot;
			s.sensor_std_range = stds[0];
			s.sensor_std_yaw = stds[1];
			s.sensor_std_pitch = stds[2];
		}
		else if (
			!(br.sensorLocationOnRobot == s.sensor_pose) || stds[0] != s.sensor_std_range ||
			stds[1] != s.sensor_std_yaw || stds[2] != s.sensor_std_pitch)
		{
			fail("several CObservationBearingRange with different sensor poses or noise in one sensory frame (not "
				 "supported)");
		}
		std::vector<CObservationBearingRange::TMeasurement> kept;
		for (const auto& m : br.sensedData)
		{
			if (!valid_reading(m, options_.require_landmark_ids))
			{
				s.skipped_readings++;
				any_skipped = true;
				continue;
			}
			kept.push_back(m);
			s.readings.push_back({m.landmarkID, m.range, m.yaw, m.pitch});
		}
		kept_per_obs.push_back(std::move(kept));
	}
	if (s.has_observation)
	{
		last_sensor_pose_ = s.sensor_pose;
		last_std_[0] = s.sensor_std_range;
		last_std_[1] = s.sensor_std_yaw;
		last_std_[2] = s.sensor_std_pitch;
	}
	else
	{
		s.sensor_pose = last_sensor_pose_;
		s.sensor_std_range = last_std_[0];
		s.sensor_std_yaw = last_std_[1];
		s.sensor_std_pitch = last_std_[2];
	}

	if (any_skipped)
	{
		auto clean = std::make_shared<CSensoryFrame>();
		std::size_t j = 0;
		for (const auto& o : *observations)
		{
			if (o && IS_CLASS(*o, CObservationBearingRange))
			{
				auto c = std::make_shared<CObservationBearingRange>(dynamic_cast<const CObservationBearingRange&>(*o));
				c->sensedData = kept_per_obs[j++];
				clean->insert(c);
			}
			else
				clean->insert(o);
		}
		s.observations = clean;
	}
	steps_++;
	return s;
}

io::RawlogStep MrptStepConverter::convert(
	const mrpt::poses::CPose3DPDFGaussian& odometry, const CObservationBearingRange& observation)
{
	mrpt::obs::CActionRobotMovement3D move;
	move.poseChange = odometry;
	auto actions = std::make_shared<CActionCollection>();
	actions->insert(move);
	auto frame = std::make_shared<CSensoryFrame>();
	frame->insert(std::make_shared<CObservationBearingRange>(observation));
	return convert(actions, frame);
}
}  // namespace swba::estimators
