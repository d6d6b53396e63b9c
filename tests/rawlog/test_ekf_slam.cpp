// MRPT's EKF run in-process over the rawlog steps.
#include <swba/estimators/ekf_slam.h>

#include <swba/eval/trajectory.h>

#include <mrpt/core/bits_math.h>

#include <gtest/gtest.h>

#include "rawlog_test_data.h"

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace
{
const std::string kIni6D = "/usr/share/mrpt/config_files/kf-slam/EKF-SLAM_6D_test.ini";

struct TumRow
{
	double t;
	Eigen::Vector3d p;
	Eigen::Quaterniond q;
};

std::vector<TumRow> read_tum(const std::string& path)
{
	std::ifstream in(path);
	EXPECT_TRUE(in.good()) << path;
	std::vector<TumRow> rows;
	std::string line;
	while (std::getline(in, line))
	{
		if (line.empty() || line[0] == '#') continue;
		std::istringstream ss(line);
		TumRow r;
		double qx, qy, qz, qw;
		ss >> r.t >> r.p.x() >> r.p.y() >> r.p.z() >> qx >> qy >> qz >> qw;
		EXPECT_FALSE(ss.fail()) << line;
		r.q = Eigen::Quaterniond(qw, qx, qy, qz);
		rows.push_back(r);
	}
	return rows;
}

const swba::io::Rawlog& demo6d()
{
	static const swba::io::Rawlog log = swba::io::read_rawlog(kDatasets + "/kf-slam_6D_demo.rawlog");
	return log;
}
}  // namespace

TEST(EkfSlam, ReproducesEvoReferenceWithIniOptions)
{
	swba::estimators::EkfSlamOptions opt;
	opt.ini_file = kIni6D;
	std::size_t progress_calls = 0;
	opt.progress = [&](std::size_t done, std::size_t total) {
		progress_calls++;
		EXPECT_EQ(total, 599u);
		EXPECT_EQ(done, progress_calls);
	};
	const auto res = swba::estimators::run_ekf_slam(demo6d().steps, opt);
	EXPECT_FALSE(res.failed) << res.failure;
	EXPECT_EQ(res.method, "kfEKFAlaDavison");
	EXPECT_NEAR(res.std_range, 0.02, 1e-7);
	EXPECT_NEAR(mrpt::RAD2DEG(res.std_yaw), 0.3, 1e-5);
	EXPECT_EQ(progress_calls, 599u);
	EXPECT_EQ(res.landmarks, demo6d().distinct_landmarks);  // every landmark seen enters the map
	const auto ref = read_tum(std::string(SWBA_DATA_DIR) + "/evo_reference/ekf_kf-slam_6D_demo.tum");
	ASSERT_EQ(ref.size(), 599u);
	ASSERT_EQ(res.poses.size(), 599u);
	double max_dp = 0, max_dq = 0;
	for (std::size_t i = 0; i < ref.size(); i++)
	{
		ASSERT_EQ(res.times[i], ref[i].t);
		const auto& P = res.poses[i];
		const Eigen::Vector3d p(P.x(), P.y(), P.z());
		mrpt::math::CQuaternionDouble q;
		P.getAsQuaternion(q);
		Eigen::Quaterniond qe(q.r(), q.x(), q.y(), q.z());
		if (qe.coeffs().dot(ref[i].q.coeffs()) < 0) qe.coeffs() *= -1;
		max_dp = std::max(max_dp, (p - ref[i].p).cwiseAbs().maxCoeff());
		max_dq = std::max(max_dq, (qe.coeffs() - ref[i].q.coeffs()).cwiseAbs().maxCoeff());
	}
	EXPECT_LE(max_dp, 1e-6);
	EXPECT_LE(max_dq, 1e-6);
}

TEST(EkfSlam, DefaultNoiseIsTheObservationsOwn)
{
	swba::estimators::EkfSlamOptions opt;
	opt.max_steps = 50;
	opt.method = "kfEKFNaive";
	const auto res = swba::estimators::run_ekf_slam(demo6d().steps, opt);
	EXPECT_FALSE(res.failed) << res.failure;
	EXPECT_EQ(res.method, "kfEKFNaive");
	EXPECT_NEAR(res.std_range, 0.01, 1e-7);
	EXPECT_NEAR(mrpt::RAD2DEG(res.std_yaw), 0.1, 1e-5);
	EXPECT_NEAR(mrpt::RAD2DEG(res.std_pitch), 0.1, 1e-5);
	EXPECT_EQ(res.poses.size(), 50u);
	EXPECT_EQ(res.times.back(), 50.0);
	EXPECT_GT(res.ms_per_step, 0.0);
	EXPECT_GT(res.cpu_ms_per_step, 0.0);
	// Explicit values override the INI's.
	opt.ini_file = kIni6D;
	opt.std_range = 0.05;
	opt.std_yaw = mrpt::DEG2RAD(0.5);
	opt.std_pitch = mrpt::DEG2RAD(0.5);
	const auto res2 = swba::estimators::run_ekf_slam(demo6d().steps, opt);
	EXPECT_EQ(res2.method, "kfEKFNaive");
	EXPECT_NEAR(res2.std_range, 0.05, 1e-7);
	EXPECT_NEAR(mrpt::RAD2DEG(res2.std_pitch), 0.5, 1e-5);
}

TEST(EkfSlam, BadOptionsThrow)
{
	swba::estimators::EkfSlamOptions opt;
	opt.method = "kfUnscented";
	EXPECT_THROW(swba::estimators::run_ekf_slam(demo6d().steps, opt), std::invalid_argument);
	opt = {};
	opt.ini_file = "/nonexistent.ini";
	EXPECT_THROW(swba::estimators::run_ekf_slam(demo6d().steps, opt), std::runtime_error);
	opt = {};
	opt.std_range = 0.0;
	EXPECT_THROW(swba::estimators::run_ekf_slam(demo6d().steps, opt), std::invalid_argument);
	EXPECT_THROW(swba::estimators::run_ekf_slam({}, {}), std::invalid_argument);
	EXPECT_EQ(swba::estimators::ekf_method_from_name("kfEKFAlaDavison"), 1);
}

TEST(EkfSlam, NoncenteredFailureIsReportedNotThrown)
{
	const auto log = swba::io::read_rawlog(kDatasets + "/kf-slam_6D_demo_noncentered.rawlog");
	swba::estimators::EkfSlamOptions opt;  // the rawlog's own noise (0.01 m, 0.1°), à la Davison
	swba::estimators::EkfSlamResult res;
	ASSERT_NO_THROW(res = swba::estimators::run_ekf_slam(log.steps, opt));
	EXPECT_TRUE(res.failed);
	EXPECT_FALSE(res.failure.empty());
	EXPECT_EQ(res.failure.find('\n'), std::string::npos);
	// With MRPT's default motion model (std_odo_z_additional = 0) it throws early (step 74 measured).
	EXPECT_GT(res.failed_step, 0u);
	EXPECT_LT(res.failed_step, 599u);
	EXPECT_NE(res.failure.find("quaternion"), std::string::npos) << res.failure;
	EXPECT_NE(res.failure.find("CRangeBearingKFSLAM.cpp:"), std::string::npos) << res.failure;
	EXPECT_EQ(res.poses.size(), res.failed_step);
	EXPECT_EQ(res.steps_processed, res.failed_step);
	EXPECT_GT(res.mrpt_warnings, 0u);
}

TEST(EkfSlam, NoncenteredWithIniAndTrueNoiseThrowsLater)
{
	// REFERENCE.md: with the kf-slam INI's motion model but the true sensor noise, à la Davison throws
	// "Vehicle pose quaternion norm is not >0" at step ≈433.
	const auto log = swba::io::read_rawlog(kDatasets + "/kf-slam_6D_demo_noncentered.rawlog");
	swba::estimators::EkfSlamOptions opt;
	opt.ini_file = "/usr/share/mrpt/config_files/kf-slam/EKF-SLAM_6D_noncentered_test.ini";
	opt.std_range = 0.01;
	opt.std_yaw = opt.std_pitch = mrpt::DEG2RAD(0.1);
	const auto res = swba::estimators::run_ekf_slam(log.steps, opt);
	EXPECT_TRUE(res.failed);
	EXPECT_GT(res.failed_step, 400u);
	EXPECT_LT(res.failed_step, 470u);
	EXPECT_EQ(res.poses.size(), res.failed_step);
}

TEST(EkfSlam, Runs2dDemo)
{
	const auto log = swba::io::read_rawlog(kDatasets + "/kf-slam_demo.rawlog");
	swba::estimators::EkfSlamOptions opt;
	const auto res = swba::estimators::run_ekf_slam(log.steps, opt);
	EXPECT_FALSE(res.failed) << res.failure;
	EXPECT_EQ(res.poses.size(), 249u);
	// A planar rawlog runs MRPT's 2D filter (range and yaw noise only: no pitch note).
	EXPECT_EQ(res.model, swba::estimators::PoseModel::Planar);
	EXPECT_EQ(res.notes.find("sensor_std_pitch"), std::string::npos) << res.notes;
	EXPECT_EQ(res.std_pitch, 0.0);
	EXPECT_FLOAT_EQ(static_cast<float>(res.std_range), static_cast<float>(log.steps.front().sensor_std_range));
	for (const auto& p : res.poses) EXPECT_TRUE(p.z() == 0.0 && p.pitch() == 0.0 && p.roll() == 0.0);
	// The 6D filter on the same data, asked for explicitly, keeps MRPT's default pitch noise (noted).
	opt.model = swba::estimators::PoseModel::Spatial;
	opt.max_steps = 5;
	const auto res6 = swba::estimators::run_ekf_slam(log.steps, opt);
	EXPECT_EQ(res6.model, swba::estimators::PoseModel::Spatial);
	EXPECT_NE(res6.notes.find("sensor_std_pitch is 0"), std::string::npos) << res6.notes;
	// The 2D demo's ground truth: the estimate after step k pairs with row k + 1.
	const auto gt = swba::eval::read_mrpt_ground_truth(kDatasets + "/kf-slam_demo_ground_truth_robot_path.txt").poses;
	ASSERT_EQ(gt.size(), 250u);
	double sq = 0;
	for (std::size_t k = 0; k < res.poses.size(); k++)
		sq += std::pow(res.poses[k].distanceTo(gt[k + 1]), 2);
	EXPECT_LT(std::sqrt(sq / double(res.poses.size())), 0.5);
}
