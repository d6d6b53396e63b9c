#include <swba/estimators/mrpt_adapter.h>

#include <mrpt/obs/CActionRobotMovement3D.h>

#include <memory>
#include <string>

namespace swba::estimators
{
using mrpt::obs::CActionCollection;
using mrpt::obs::CObservationBearingRange;
using mrpt::obs::CSensoryFrame;

io::RawlogStep MrptStepConverter::convert(const CActionCollection::Ptr& actions, const CSensoryFrame::Ptr& observations)
{
	// The same conversion as io::read_rawlog (io::RawlogStepConverter); dropped readings are counted
	// in RawlogStep::skipped_readings.
	return converter_.convert(actions, observations, "step " + std::to_string(converter_.steps()));
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
