// Tests of the inertial simulator: its analytic derivatives against finite differences, midpoint dead
// reckoning of its noise-free readings, determinism per seed and the noise it declares.
#include <swba/core/lie.h>
#include <swba/problems/inertial_simulation.h>

#include <gtest/gtest.h>

#include <cmath>

using namespace swba;
using namespace swba::problems;

namespace
{
const InertialTrajectoryKind kKinds[] = {InertialTrajectoryKind::FigureEight, InertialTrajectoryKind::Car};

NavState nav_of(const InertialTruth& x)
{
	NavState s;
	s.R = x.pose.getRotationMatrix().asEigen();
	s.p = Eigen::Vector3d(x.pose.x(), x.pose.y(), x.pose.z());
	s.v = x.v;
	return s;
}
}  // namespace

TEST(InertialSimulation, KinematicsMatchFiniteDifferences)
{
	const double h = 1e-5;
	for (auto kind : kKinds)
		for (double t : {0.3, 3.7, 7.5, 12.1, 29.9})
		{
			const Kinematics k = trajectory_kinematics(kind, t), kp = trajectory_kinematics(kind, t + h),
							 km = trajectory_kinematics(kind, t - h);
			const std::string at = enum_name(kind) + " t=" + std::to_string(t);
			EXPECT_LT(((kp.p - km.p) / (2 * h) - k.v).norm(), 1e-6) << at;
			EXPECT_LT(((kp.v - km.v) / (2 * h) - k.a).norm(), 1e-6) << at;
			const Eigen::Vector3d w = (so3_log(k.R.transpose() * kp.R) - so3_log(k.R.transpose() * km.R)) / (2 * h);
			EXPECT_LT((w - k.omega).norm(), 1e-6) << at;
		}
}

// The midpoint scheme's error falls with Δt²: on the figure-eight it is 6.5 mm at 100 Hz, 1.6 mm at
// 200 Hz; the bound is checked at 200 and 400 Hz.
TEST(InertialSimulation, MidpointDeadReckoningOfNoiseFreeReadingsStaysWithin2mmOver20s)
{
	for (auto kind : kKinds)
		for (double rate : {200.0, 400.0})
		{
			InertialSimulationOptions o;
			o.trajectory = kind;
			o.duration = 20;
			o.imu_rate = rate;
			o.noise_free = true;
			const InertialDataset d = simulate_inertial(o);
			NavState x = nav_of(d.truth.front());
			double worst = 0;
			for (size_t k = 1; k < d.imu.size(); k++)
			{
				x = imu_midpoint_step(x, d.imu[k - 1], d.imu[k], Vector6d::Zero(), d.noise.gravity);
				worst = std::max(worst, (x.p - nav_of(d.truth[k]).p).norm());
			}
			EXPECT_LT(worst, 2e-3) << enum_name(kind) << " at " << rate << " Hz";
			std::printf("[dead reckoning] %-8s %3.0f Hz, 20 s: worst position error %.3g m\n",
						enum_name(kind).c_str(), rate, worst);
		}
}

TEST(InertialSimulation, DeterministicPerSeed)
{
	InertialSimulationOptions o;
	o.duration = 5;
	const InertialDataset a = simulate_inertial(o), b = simulate_inertial(o);
	ASSERT_EQ(a.imu.size(), b.imu.size());
	for (size_t k = 0; k < a.imu.size(); k++) ASSERT_EQ(a.imu[k].acc, b.imu[k].acc);
	ASSERT_EQ(a.pose_priors.size(), 51u);
	EXPECT_EQ(a.pose_priors[7].pose.asVectorVal(), b.pose_priors[7].pose.asVectorVal());
	o.seed = 2;
	const InertialDataset c = simulate_inertial(o);
	EXPECT_NE(a.imu[10].acc, c.imu[10].acc);
	EXPECT_NE(a.odometry[3].pose.asVectorVal(), c.odometry[3].pose.asVectorVal());
}

TEST(InertialSimulation, PosePriorNoiseHasTheDeclaredSigma)
{
	InertialSimulationOptions o;
	o.duration = 100;
	o.pose_sigma_m = 0.5;
	o.pose_sigma_rad = 0.02;
	const InertialDataset d = simulate_inertial(o);
	Eigen::Matrix<double, 6, 1> ss = Eigen::Matrix<double, 6, 1>::Zero();
	size_t j = 0;
	for (const auto& z : d.pose_priors)
	{
		while (d.truth[j].t < z.t - 1e-9) j++;
		const mrpt::poses::CPose3D E = z.pose - d.truth[j].pose;  // truth⁻¹ ⊕ measured
		Eigen::Matrix<double, 6, 1> e;
		e << E.x(), E.y(), E.z(), so3_log(E.getRotationMatrix().asEigen());
		ss += e.cwiseAbs2();
	}
	const Eigen::Matrix<double, 6, 1> sd = (ss / double(d.pose_priors.size())).cwiseSqrt();
	for (int i = 0; i < 3; i++) EXPECT_NEAR(sd[i] / 0.5, 1.0, 0.1) << i;
	for (int i = 3; i < 6; i++) EXPECT_NEAR(sd[i] / 0.02, 1.0, 0.1) << i;
	EXPECT_DOUBLE_EQ(d.pose_priors[0].covariance(0, 0), 0.25);
}

TEST(InertialSimulation, CarStopsAndTurns)
{
	InertialSimulationOptions o;
	o.trajectory = InertialTrajectoryKind::Car;
	o.noise_free = true;
	const InertialDataset d = simulate_inertial(o);
	double vmax = 0, wmax = 0;
	int stops = 0;
	bool moving = false;
	for (const auto& x : d.truth)
	{
		vmax = std::max(vmax, x.v.norm());
		if (moving && x.v.norm() < 1e-3)
		{
			stops++;
			moving = false;
		}
		if (x.v.norm() > 0.5) moving = true;
	}
	for (const auto& s : d.imu) wmax = std::max(wmax, std::abs(s.gyro.z()));
	EXPECT_GE(stops, 3);
	EXPECT_GT(vmax, 3.0);
	EXPECT_GT(wmax, 0.3);
	EXPECT_LT(std::abs(d.truth.back().pose.z()), 1e-12);
}

TEST(InertialSimulation, RejectsRatesThatDoNotDivide)
{
	InertialSimulationOptions o;
	o.pose_rate = 7;
	EXPECT_THROW(o.validate(), std::invalid_argument);
	o.pose_rate = 0;
	EXPECT_NO_THROW(o.validate());
}

TEST(InertialSimulation, OdometryIncrementNoiseHasTheDeclaredCovariance)
{
	InertialSimulationOptions o;
	o.duration = 200;
	const InertialDataset d = simulate_inertial(o);
	Eigen::Matrix<double, 6, 1> z2 = Eigen::Matrix<double, 6, 1>::Zero();
	const int every = int(o.imu_rate / o.odometry_rate);
	for (size_t k = 1; k < d.odometry.size(); k++)
	{
		const mrpt::poses::CPose3D D = d.odometry[k].pose - d.odometry[k - 1].pose;	 // measured increment
		const mrpt::poses::CPose3D T = d.truth[k * every].pose - d.truth[(k - 1) * every].pose;
		const mrpt::poses::CPose3D E = T - D;  // D⁻¹ ⊕ T
		Eigen::Matrix<double, 6, 1> e;
		e << E.x(), E.y(), E.z(), so3_log(E.getRotationMatrix().asEigen());
		for (int i = 0; i < 6; i++) z2[i] += e[i] * e[i] / d.odometry[k].covariance(i, i);
	}
	z2 /= double(d.odometry.size() - 1);
	for (int i = 0; i < 6; i++) EXPECT_NEAR(z2[i], 1.0, 0.1) << i;
}
