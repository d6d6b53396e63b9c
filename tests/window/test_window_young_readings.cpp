// Young landmarks' readings (SlidingWindowOptions::young_landmark_readings, young_readings_test): a pose
// that holds one stays re-linearised, and with the test only while the readings misfit their declared noise.
#include "window_test_utils.h"

#include <gtest/gtest.h>

#include <cstddef>

namespace
{
using namespace swba;
using namespace swba::estimators;

/** The first `n` steps of kf-slam_6D_demo. */
io::Rawlog young_demo_prefix(std::size_t n)
{
	io::Rawlog r = test::demo_rawlog();
	r.steps.resize(n);
	return r;
}

struct YoungRun
{
	eval::Trajectory online;
	ReadingCounts counts;
};

YoungRun young_run(const io::Rawlog& r, const SlidingWindowOptions& o)
{
	SlidingWindowEstimator est(o);
	for (const auto& s : r.steps) est.process(s);
	est.finish();
	return {est.online_trajectory(), est.reading_counts()};
}

/** `n`: young_landmark_readings (0: the rule off); `test`: young_readings_test. */
SlidingWindowOptions young_options(int n, bool test)
{
	SlidingWindowOptions o;
	o.window_size = 10;
	o.covariances = false;
	o.young_landmark_readings = n;
	o.young_readings_test = test;
	return o;
}
}  // namespace

// With every landmark young for the whole run, every pose with a reading stays re-linearised until the
// window is full: on a log whose every step has readings that is the whole window re-linearised.
TEST(YoungReadings, AlwaysYoungEqualsTheWholeWindowReLinearised)
{
	const io::Rawlog r = young_demo_prefix(60);
	for (const auto& s : r.steps) ASSERT_FALSE(s.readings.empty()) << "step " << s.index;
	const SlidingWindowOptions held = young_options(1000000, false);
	SlidingWindowOptions whole = young_options(0, true);
	whole.relinearized_poses = 0;
	const YoungRun a = young_run(r, held), b = young_run(r, whole);
	// From the third step on: at the second the oldest pose is the initial one, which has no reading.
	EXPECT_EQ(a.counts.young_held_steps, 60u - 2u);
	ASSERT_EQ(a.online.size(), b.online.size());
	// A copy: asEigen() maps the temporary matrix, which dies with the return statement.
	const auto matrix = [](const mrpt::poses::CPose3D& p) -> Eigen::Matrix4d {
		return p.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>().asEigen();
	};
	for (std::size_t k = 0; k < a.online.size(); k++)
		EXPECT_LT((matrix(a.online.poses[k]) - matrix(b.online.poses[k])).norm(), 1e-9) << "step " << k;
}

// The test: on the simulated log the readings fit their declared noise, which the test finds within a few
// steps; declared at half their σ (a quarter of the variance) they do not, and the rule keeps running.
TEST(YoungReadings, TestStopsTheRuleWhenTheReadingsFitTheirDeclaredNoise)
{
	const io::Rawlog r = young_demo_prefix(150);
	const YoungRun declared = young_run(r, young_options(30, true));
	SlidingWindowOptions halved = young_options(30, true);
	const Eigen::Vector3d sigma = halved.sensor.resolve(r.steps[1]);
	halved.sensor.std_range = sigma[0] / 2;
	halved.sensor.std_yaw = sigma[1] / 2;
	halved.sensor.std_pitch = sigma[2] / 2;
	const YoungRun misfit = young_run(r, halved);
	EXPECT_GT(declared.counts.young_held_steps, 0u);  // held until decided
	EXPECT_LT(declared.counts.young_held_steps, 40u);
	EXPECT_GT(misfit.counts.young_held_steps, 100u);
	const YoungRun off = young_run(r, young_options(0, true));
	EXPECT_EQ(off.counts.young_held_steps, 0u);
}
