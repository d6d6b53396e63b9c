// MrptStepConverter / MrptSlidingWindow (swba/estimators/mrpt_adapter.h): MRPT objects fed one by one
// must become the same steps io::read_rawlog makes from the file, and invalid data must be rejected
// with the step named.
#include <gtest/gtest.h>
#include <swba/estimators/mrpt_adapter.h>

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CActionRobotMovement3D.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/serialization/CArchive.h>

#include <cmath>
#include <limits>
#include <string>

using namespace swba;
using namespace swba::estimators;

namespace
{
const std::string kDemo = std::string(SWBA_MRPT_DATASETS) + "/kf-slam_6D_demo.rawlog";

void expect_same_step(const io::RawlogStep& a, const io::RawlogStep& b)
{
	EXPECT_EQ(a.index, b.index);
	EXPECT_EQ(a.has_odometry, b.has_odometry);
	EXPECT_EQ(a.odometry_is_2d, b.odometry_is_2d);
	for (int i = 0; i < 6; i++)
	{
		EXPECT_EQ(a.odometry.mean[i], b.odometry.mean[i]) << "step " << a.index << " coordinate " << i;
		for (int j = 0; j < 6; j++) EXPECT_EQ(a.odometry.cov(i, j), b.odometry.cov(i, j));
	}
	EXPECT_EQ(a.has_observation, b.has_observation);
	ASSERT_EQ(a.readings.size(), b.readings.size()) << "step " << a.index;
	for (std::size_t i = 0; i < a.readings.size(); i++)
	{
		EXPECT_EQ(a.readings[i].landmark_id, b.readings[i].landmark_id);
		EXPECT_EQ(a.readings[i].range, b.readings[i].range);
		EXPECT_EQ(a.readings[i].yaw, b.readings[i].yaw);
		EXPECT_EQ(a.readings[i].pitch, b.readings[i].pitch);
	}
	EXPECT_EQ(a.skipped_readings, b.skipped_readings);
	EXPECT_TRUE(a.sensor_pose == b.sensor_pose);
	EXPECT_EQ(a.sensor_std_range, b.sensor_std_range);
	EXPECT_EQ(a.sensor_std_yaw, b.sensor_std_yaw);
	EXPECT_EQ(a.sensor_std_pitch, b.sensor_std_pitch);
}

mrpt::obs::CObservationBearingRange one_reading(int32_t id, double range)
{
	mrpt::obs::CObservationBearingRange obs;
	obs.sensor_std_range = 0.01;
	obs.sensor_std_yaw = obs.sensor_std_pitch = 0.1 * M_PI / 180;
	mrpt::obs::CObservationBearingRange::TMeasurement m;
	m.landmarkID = id;
	m.range = range;
	m.yaw = 0.1;
	m.pitch = -0.05;
	obs.sensedData.push_back(m);
	return obs;
}

mrpt::poses::CPose3DPDFGaussian forward(double dx)
{
	mrpt::poses::CPose3DPDFGaussian odo;
	odo.mean = mrpt::poses::CPose3D(dx, 0, 0, 0, 0, 0);
	odo.cov.setIdentity();
	odo.cov *= 1e-4;
	return odo;
}
}  // namespace

TEST(MrptAdapter, PairsFedOneByOneGiveTheReadersSteps)
{
	io::RawlogReaderOptions ro;
	ro.max_steps = 120;
	const io::Rawlog rawlog = io::read_rawlog(kDemo, ro);

	mrpt::io::CFileGZInputStream f(kDemo);
	auto arch = mrpt::serialization::archiveFrom(f);
	MrptStepConverter conv;
	mrpt::obs::CActionCollection::Ptr acts;
	mrpt::obs::CSensoryFrame::Ptr sf;
	std::size_t entry = 0;
	std::size_t n = 0;
	while (n < rawlog.steps.size() && mrpt::obs::CRawlog::readActionObservationPair(arch, acts, sf, entry))
	{
		const io::RawlogStep s = conv.convert(acts, sf);
		expect_same_step(s, rawlog.steps[n]);
		n++;
	}
	EXPECT_EQ(n, rawlog.steps.size());
	EXPECT_EQ(conv.steps(), n);
}

TEST(MrptAdapter, OdometryAndObservationOverload)
{
	MrptStepConverter conv;
	const auto s0 = conv.convert(forward(0.5), one_reading(7, 3.0));
	EXPECT_EQ(s0.index, 0u);
	EXPECT_TRUE(s0.has_odometry);
	EXPECT_FALSE(s0.odometry_is_2d);
	EXPECT_DOUBLE_EQ(s0.odometry.mean.x(), 0.5);
	ASSERT_EQ(s0.readings.size(), 1u);
	EXPECT_EQ(s0.readings[0].landmark_id, 7);
	EXPECT_DOUBLE_EQ(s0.readings[0].range, 3.0);
	EXPECT_EQ(s0.sensor_std_range, static_cast<double>(0.01f));  // MRPT stores the noise as float
	const auto s1 = conv.convert(forward(0.5), one_reading(7, 2.5));
	EXPECT_EQ(s1.index, 1u);
	EXPECT_DOUBLE_EQ(s1.time(), 2.0);
}

TEST(MrptAdapter, InvalidReadingsAreDroppedAndCounted)
{
	MrptStepConverter conv;
	auto obs = one_reading(3, 2.0);
	auto bad = obs.sensedData[0];
	bad.range = std::numeric_limits<double>::quiet_NaN();
	obs.sensedData.push_back(bad);
	bad = obs.sensedData[0];
	bad.landmarkID = -1;  // unknown ID: needs data association
	obs.sensedData.push_back(bad);
	const auto s = conv.convert(forward(0.1), obs);
	EXPECT_EQ(s.readings.size(), 1u);
	EXPECT_EQ(s.skipped_readings, 2u);
	// The frame handed on (e.g. to MRPT's EKF) holds only the valid reading.
	auto kept = s.observations->getObservationByClass<mrpt::obs::CObservationBearingRange>();
	ASSERT_TRUE(kept);
	EXPECT_EQ(kept->sensedData.size(), 1u);
}

TEST(MrptAdapter, InvalidInputThrowsNamingTheStepAndDoesNotAdvance)
{
	MrptStepConverter conv;
	conv.convert(forward(0.1), one_reading(1, 1.0));
	auto nan_odo = forward(0.1);
	nan_odo.mean.x(std::numeric_limits<double>::quiet_NaN());
	try
	{
		conv.convert(nan_odo, one_reading(1, 1.0));
		FAIL() << "a non-finite odometry mean was accepted";
	}
	catch (const std::invalid_argument& e)
	{
		EXPECT_NE(std::string(e.what()).find("step 1"), std::string::npos) << e.what();
		EXPECT_NE(std::string(e.what()).find("odometry mean"), std::string::npos) << e.what();
	}
	EXPECT_EQ(conv.steps(), 1u);
	EXPECT_THROW(conv.convert(nullptr, std::make_shared<mrpt::obs::CSensoryFrame>()), std::invalid_argument);
	auto neg = forward(0.1);
	neg.cov(2, 2) = -1;
	EXPECT_THROW(conv.convert(neg, one_reading(1, 1.0)), std::invalid_argument);
	EXPECT_EQ(conv.steps(), 1u);
}

TEST(MrptAdapter, EstimatorFedFromMrptObjectsMatchesRawlogSteps)
{
	io::RawlogReaderOptions ro;
	ro.max_steps = 40;
	const io::Rawlog rawlog = io::read_rawlog(kDemo, ro);
	SlidingWindowOptions opt;
	opt.window_size = 5;
	SlidingWindowEstimator reference(opt);
	for (const auto& s : rawlog.steps) reference.process(s);

	MrptSlidingWindow slam(opt);
	for (const auto& s : rawlog.steps) slam.process(s.actions, s.observations);
	const auto a = reference.current_pose(), b = slam.current_pose();
	for (int i = 0; i < 6; i++) EXPECT_EQ(a[i], b[i]) << "coordinate " << i;
	EXPECT_EQ(slam.window_poses().size(), reference.window_poses().size());
	EXPECT_EQ(slam.landmarks().size(), reference.landmarks().size());
	EXPECT_EQ(slam.step_summaries().size(), rawlog.steps.size());
	EXPECT_GT(slam.landmarks().size(), 0u);
}
