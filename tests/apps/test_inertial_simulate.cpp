// swba simulate-imu end to end: the rawlog it writes reads back (through the observation-rawlog reader)
// to the simulated data set, with the covariances it declared.
#include <swba/apps/inertial_simulate.h>
#include <swba/eval/trajectory.h>
#include <swba/io/observation_rawlog.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>

using namespace swba;
namespace fs = std::filesystem;

TEST(InertialSimulate, RawlogReadsBackToTheSimulatedData)
{
	apps::InertialSimulateOptions o;
	o.simulation.duration = 6;
	o.simulation.trajectory = problems::InertialTrajectoryKind::Car;
	o.out_dir = (fs::temp_directory_path() / "swba_test_inertial_simulate").string();
	std::ostringstream log;
	const apps::SimulatedInertialRawlog out = apps::simulate_inertial_rawlog(o, log);
	const problems::InertialDataset d = problems::simulate_inertial(o.simulation);
	ASSERT_TRUE(io::is_observation_rawlog(out.rawlog));
	io::SensorRoles roles;
	roles.odometry = {apps::kSimulatedOdometryLabel};
	const io::ObservationRawlog r = io::read_observation_rawlog(out.rawlog, roles);
	ASSERT_EQ(r.imu.size(), d.imu.size());
	ASSERT_EQ(r.pose_priors.size(), d.pose_priors.size());
	ASSERT_EQ(r.odometry.size(), d.odometry.size());
	for (size_t k = 0; k < d.imu.size(); k++)
	{
		ASSERT_NEAR(r.imu[k].t, d.imu[k].t, 1e-12);
		ASSERT_EQ(r.imu[k].acc, d.imu[k].acc);
		ASSERT_EQ(r.imu[k].gyro, d.imu[k].gyro);
	}
	for (size_t k = 0; k < d.pose_priors.size(); k++)
	{
		EXPECT_LT((r.pose_priors[k].pose.asVectorVal() - d.pose_priors[k].pose.asVectorVal()).norm(), 1e-12);
		EXPECT_LT((r.pose_priors[k].covariance - d.pose_priors[k].covariance).norm(), 1e-12);
	}
	for (size_t k = 1; k < d.odometry.size(); k++)
		EXPECT_LT((r.odometry[k].covariance - d.odometry[k].covariance).norm(), 1e-12 * d.odometry[k].covariance.norm()) << k;
	const eval::Trajectory gt = eval::read_tum(out.ground_truth);
	ASSERT_EQ(gt.size(), d.truth.size());
	EXPECT_LT((gt.poses.back().asVectorVal() - d.truth.back().pose.asVectorVal()).norm(), 1e-8);
	EXPECT_EQ(eval::read_mrpt_ground_truth(out.robot_path).size(), d.pose_priors.size());
}
