// Tests of the observation-format rawlog reader on files written with plain MRPT calls (no swba writer):
// field order of CObservationIMU, roles by label, times, sensor poses and covariance conversion.
#include <swba/core/lie.h>
#include <swba/io/observation_rawlog.h>
#include <swba/io/rawlog.h>

#include <gtest/gtest.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <mrpt/serialization/CArchive.h>

#include <filesystem>
#include <string>

using namespace swba;
using mrpt::poses::CPose3D;
namespace fs = std::filesystem;

namespace
{
const double kT0 = 1.7e9;  // an arbitrary MRPT time (Unix seconds)

mrpt::Clock::time_point at(double t) { return mrpt::Clock::fromDouble(kT0) + std::chrono::milliseconds(std::lround(t * 1000)); }

mrpt::obs::CObservationRobotPose::Ptr robot_pose(double t, const std::string& label, const CPose3D& p, double var_xyz,
												 double var_yaw, double var_pitch, double var_roll,
												 const CPose3D& sensor = CPose3D())
{
	auto o = mrpt::obs::CObservationRobotPose::Create();
	o->timestamp = at(t);
	o->sensorLabel = label;
	o->pose.mean = p;
	o->pose.cov.setZero();
	for (int i = 0; i < 3; i++) o->pose.cov(i, i) = var_xyz;
	o->pose.cov(3, 3) = var_yaw;
	o->pose.cov(4, 4) = var_pitch;
	o->pose.cov(5, 5) = var_roll;
	o->sensorPose = sensor;
	return o;
}

/** A rawlog written the way an MRPT driver writes one: bare observations, one archive. */
std::string write_plain_rawlog(const CPose3D& lidar_on_body)
{
	// Named after the running test: ctest runs the tests of this file in parallel processes.
	const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
	const fs::path path =
		fs::temp_directory_path() / ("swba_test_observation_rawlog_" + std::string(info->name()) + ".rawlog");
	mrpt::io::CFileGZOutputStream f(path.string());
	auto arch = mrpt::serialization::archiveFrom(f);
	for (int k = 0; k <= 20; k++)
	{
		auto imu = mrpt::obs::CObservationIMU::Create();
		imu->timestamp = at(0.01 * k);
		imu->sensorLabel = "XSENS";
		imu->set(mrpt::obs::IMU_X_ACC, 0.1 * k);
		imu->set(mrpt::obs::IMU_Y_ACC, -0.2);
		imu->set(mrpt::obs::IMU_Z_ACC, 9.81);
		imu->set(mrpt::obs::IMU_WX, 1.0);
		imu->set(mrpt::obs::IMU_WY, 2.0);
		imu->set(mrpt::obs::IMU_WZ, 3.0);
		arch << *imu;
		if (k % 10 == 0)
		{
			// Map matching measures the lidar's pose: the body at (k, 0, 0) with yaw 0.3.
			const CPose3D body(k, 0, 0, 0.3, 0, 0);
			arch << *robot_pose(0.01 * k, "MAP", body + lidar_on_body, 0.25, 0.01, 0.02, 0.03, lidar_on_body);
			arch << *robot_pose(0.01 * k, "LIDAR_ODOM", CPose3D(0.5 * k, 0, 0, 0.1 * k, 0, 0), 0.04, 1e-4, 2e-4, 3e-4);
			auto odo = mrpt::obs::CObservationOdometry::Create();  // a class the reader does not use
			odo->timestamp = at(0.01 * k);
			arch << *odo;
		}
	}
	return path.string();
}
}  // namespace

TEST(ObservationRawlog, ImuFieldsAreReadByNameInZYXOrder)
{
	mrpt::obs::CObservationIMU o;
	o.set(mrpt::obs::IMU_WX, 1.0);
	o.set(mrpt::obs::IMU_WZ, 3.0);
	EXPECT_EQ(o.rawMeasurements[3], 3.0);  // the gyro indices run z, y, x
	EXPECT_EQ(o.rawMeasurements[5], 1.0);
}

TEST(ObservationRawlog, ReadsAFileWrittenWithPlainMrptCalls)
{
	const CPose3D lidar(0.5, 0.1, 0.2, M_PI / 2, 0, 0);
	const std::string path = write_plain_rawlog(lidar);
	ASSERT_TRUE(io::is_observation_rawlog(path));
	io::SensorRoles roles;
	roles.odometry = {"LIDAR_ODOM"};
	const io::ObservationRawlog log = io::read_observation_rawlog(path, roles);
	EXPECT_EQ(log.entries, 21u + 3u * 3u);
	EXPECT_EQ(log.ignored_entries, 3u);
	EXPECT_NEAR(log.time_origin, kT0, 1e-6);
	ASSERT_EQ(log.imu.size(), 21u);
	EXPECT_DOUBLE_EQ(log.imu[7].t, 0.07);
	EXPECT_EQ(log.imu[7].acc, Eigen::Vector3d(0.1 * 7, -0.2, 9.81));
	EXPECT_EQ(log.imu[7].gyro, Eigen::Vector3d(1, 2, 3));
	ASSERT_EQ(log.pose_priors.size(), 3u);
	ASSERT_EQ(log.odometry.size(), 3u);
	// The prior is converted from the lidar to the body (IMU) frame.
	const CPose3D expected(10, 0, 0, 0.3, 0, 0);
	EXPECT_DOUBLE_EQ(log.pose_priors[1].t, 0.1);
	EXPECT_LT((log.pose_priors[1].pose.asVectorVal() - expected.asVectorVal()).norm(), 1e-12);
	EXPECT_EQ(log.odometry[2].label, "LIDAR_ODOM");
	EXPECT_NEAR(log.odometry[2].pose.yaw(), 2.0, 1e-12);
}

TEST(ObservationRawlog, CovarianceIsConvertedToTheLocalTangent)
{
	// Zero pitch and roll: (yaw, pitch, roll) variances become the tangent's (ω_z, ω_y, ω_x).
	const std::string path = write_plain_rawlog(CPose3D());
	io::SensorRoles roles;
	roles.pose_prior = {"MAP"};
	const io::ObservationRawlog log = io::read_observation_rawlog(path, roles);
	EXPECT_TRUE(log.odometry.empty());
	EXPECT_EQ(log.ignored_entries, 3u + 3u);
	const Eigen::Matrix<double, 6, 6>& S = log.pose_priors[0].covariance;
	for (int i = 0; i < 3; i++) EXPECT_NEAR(S(i, i), 0.25, 1e-12);
	EXPECT_NEAR(S(3, 3), 0.03, 1e-12);	// roll
	EXPECT_NEAR(S(4, 4), 0.02, 1e-12);	// pitch
	EXPECT_NEAR(S(5, 5), 0.01, 1e-12);	// yaw
}

TEST(ObservationRawlog, SensorOffsetMovesTheCovarianceByTheAdjoint)
{
	// A rotation error ω about z of the lidar, mounted 1 m ahead of the body, moves the body (1 m behind
	// it) by ω·ẑ × (−x̂) = −ω·ŷ: the body's y error is the yaw error's negative times 1 m.
	const CPose3D lidar(1, 0, 0, 0, 0, 0);
	const std::string path = write_plain_rawlog(lidar);
	io::SensorRoles roles;
	roles.pose_prior = {"MAP", "LIDAR_ODOM"};
	const io::ObservationRawlog log = io::read_observation_rawlog(path, roles);
	ASSERT_EQ(log.pose_priors.size(), 6u);	// both labels named as priors
	const Eigen::Matrix<double, 6, 6>& S = log.pose_priors[0].covariance;
	EXPECT_NEAR(S(1, 1), 0.25 + 0.01 * 1.0, 1e-12);	 // y picks up yaw variance × 1 m²
	EXPECT_NEAR(S(1, 5), -0.01, 1e-12);
	EXPECT_NEAR(S(0, 0), 0.25, 1e-12);
}

TEST(ObservationRawlog, RejectsAmbiguousRolesAndTwoImus)
{
	const std::string path = write_plain_rawlog(CPose3D());
	io::SensorRoles roles;
	roles.pose_prior = {"MAP"};
	roles.odometry = {"MAP"};
	EXPECT_THROW(io::read_observation_rawlog(path, roles), std::runtime_error);
	// Two pose labels and no role named: each could be the prior or a drifting odometry.
	try
	{
		io::read_observation_rawlog(path, {});
		ADD_FAILURE() << "two pose-prior labels by default were accepted";
	}
	catch (const std::runtime_error& e)
	{
		EXPECT_NE(std::string(e.what()).find("labels 'MAP' and 'LIDAR_ODOM' would both be global pose priors"),
				  std::string::npos)
			<< e.what();
	}
	io::SensorRoles keys_roles;
	const auto keys = io::SensorRoles::ini_keys("sensors");
	ASSERT_EQ(keys.size(), 3u);
	keys[2].set(" LIDAR_ODOM , WHEELS", keys_roles);
	EXPECT_EQ(keys_roles.odometry, (std::vector<std::string>{"LIDAR_ODOM", "WHEELS"}));
	EXPECT_EQ(keys[2].get(keys_roles), "LIDAR_ODOM,WHEELS");
}

TEST(ObservationRawlog, ActionSensoryFrameRawlogIsNotObservationFormat)
{
	const std::string demo = std::string(SWBA_MRPT_DATASETS) + "/kf-slam_6D_demo.rawlog";
	if (!fs::exists(demo)) GTEST_SKIP() << demo << " not installed";
	EXPECT_FALSE(io::is_observation_rawlog(demo));
}
