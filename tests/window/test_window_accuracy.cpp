// Accuracy of the window off its default path, each against an independent reference where one
// exists: XYZ landmarks against the inverse-depth window and the batch, the prior gauge against the
// fixed gauge, a sensor mounted off the robot's centre against the batch on the same data, and the
// constant-time policy against its measured figure (it forgets the map, so nothing else bounds it).
#include <gtest/gtest.h>

#include "window_test_utils.h"

#include <cstdio>

using namespace swba;
using namespace swba::estimators;

namespace
{
struct Ape
{
	double online = 0, lagged = 0;
};

Ape window_ape(const io::Rawlog& rawlog, const std::string& gt_file, const SlidingWindowOptions& opt)
{
	SlidingWindowEstimator est(opt);
	for (const auto& s : rawlog.steps) est.process(s);
	est.finish();
	const eval::Trajectory gt = test::ground_truth(test::dataset(gt_file));
	return {test::ape_trans_rmse(gt, est.online_trajectory()), test::ape_trans_rmse(gt, est.lagged_trajectory())};
}

double batch_ape(const io::Rawlog& rawlog, const std::string& gt_file, const SlidingWindowOptions& opt)
{
	const eval::Trajectory gt = test::ground_truth(test::dataset(gt_file));
	return test::ape_trans_rmse(gt, run_batch(rawlog, opt).trajectory);
}

SlidingWindowOptions w10()
{
	SlidingWindowOptions opt;
	opt.window_size = 10;
	return opt;
}

const char* kDemoGt = "kf-slam_6D_demo_ground_truth_robot_path.txt";
}  // namespace

TEST(WindowAccuracy, XyzLandmarksMatchTheInverseDepthWindowAndStayCloseToBatch)
{
	SlidingWindowOptions xyz = w10();
	xyz.landmarks = LandmarkParameterization::Xyz;
	const Ape a = window_ape(test::demo_rawlog(), kDemoGt, xyz);
	const Ape ref = window_ape(test::demo_rawlog(), kDemoGt, w10());
	const double batch = batch_ape(test::demo_rawlog(), kDemoGt, w10());
	std::printf("[accuracy] xyz W=10 online %.6f lagged %.6f; inverse depth %.6f / %.6f; batch %.6f\n", a.online,
				a.lagged, ref.online, ref.lagged, batch);
	// Same information, another chart of the landmarks: the estimates agree to well under a millimetre.
	EXPECT_NEAR(a.online, ref.online, 0.005 * ref.online);
	EXPECT_NEAR(a.lagged, ref.lagged, 0.005 * ref.lagged);
	EXPECT_LT(a.lagged, 1.02 * batch);  // measured 1.008
}

TEST(WindowAccuracy, PriorGaugeMatchesTheFixedGauge)
{
	SlidingWindowOptions prior = w10();
	prior.gauge = GaugeMode::Prior;  // information 1e8 on the first pose: fixed to 1e-4 m / rad
	const Ape a = window_ape(test::demo_rawlog(), kDemoGt, prior);
	const Ape fixed = window_ape(test::demo_rawlog(), kDemoGt, w10());
	std::printf("[accuracy] prior gauge W=10 online %.6f lagged %.6f; fixed %.6f / %.6f\n", a.online, a.lagged,
				fixed.online, fixed.lagged);
	EXPECT_NEAR(a.online, fixed.online, 0.001 * fixed.online);
	EXPECT_NEAR(a.lagged, fixed.lagged, 0.001 * fixed.lagged);
}

TEST(WindowAccuracy, SensorOffTheRobotCentreStaysAsAccurateAsBatch)
{
	// kf-slam_6D_demo_noncentered: the sensor is mounted away from the robot's origin (sensorPose in
	// the observations), so every factor goes through the sensor-on-robot transform.
	const io::Rawlog& rawlog = test::cached_rawlog("kf-slam_6D_demo_noncentered.rawlog");
	const char* gt = "kf-slam_6D_demo_noncentered_ground_truth_robot_path.txt";
	// Least squares, the model this rawlog was simulated from: the sensor transform is the subject. With
	// the default Cauchy loss the window gives up a little more than the batch on this clean rawlog
	// (lagged 1.03x, online 1.07x the batch; doc/realdata.md).
	SlidingWindowOptions ls = w10();
	ls.robust_loss = RobustLoss::None;
	const Ape a = window_ape(rawlog, gt, ls);
	const double batch = batch_ape(rawlog, gt, ls);
	std::printf("[accuracy] noncentred W=10 online %.6f lagged %.6f; batch %.6f\n", a.online, a.lagged, batch);
	EXPECT_LT(a.lagged, 1.01 * batch);  // measured 0.995
	EXPECT_LT(a.online, 1.05 * batch);  // measured 1.028
	// Window and batch share the graph, so the ratios cannot see a sensor offset both ignore; MRPT's EKF
	// diverges on this rawlog (step 74), so the absolute anchor is the batch's measured figure + 5 %.
	EXPECT_LT(batch, 1.05 * 0.007958);
}

TEST(WindowAccuracy, ConstantTimePolicyKeepsItsMeasuredAccuracy)
{
	// The constant-time policy marginalises the landmarks no window pose sees: it forgets the map and
	// drifts on a run that revisits it (0.069 m against the SLAM policy's 0.012 m, W = 10). Nothing
	// independent bounds that drift, so the bound is the measured figure + 5 %.
	SlidingWindowOptions ct = w10();
	ct.policy = LandmarkPolicy::ConstantTime;
	const Ape a = window_ape(test::demo_rawlog(), kDemoGt, ct);
	std::printf("[accuracy] constant-time W=10 online %.6f lagged %.6f\n", a.online, a.lagged);
	EXPECT_LT(a.online, 1.05 * 0.069376);
	EXPECT_LT(a.lagged, 1.05 * 0.069233);
}
