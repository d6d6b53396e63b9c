// The error-state Kalman filter on simulated data: exact tracking of noise-free data, fusion better
// than each dead reckoning, and consistency (NEES) over Monte-Carlo runs.
#include <swba/core/chi2.h>
#include <swba/core/lie.h>
#include <swba/estimators/inertial_filter.h>
#include <swba/problems/inertial_simulation.h>

#include "inertial_test_utils.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>

#include <cmath>

using namespace swba;
using namespace swba::estimators;
using namespace swba::problems;

namespace
{
using test::input_of;
using test::position;
using test::rmse;
using test::truth_at;

InertialFilterOptions filter_options(const InertialDataset& d, ImuGrade grade)
{
	InertialFilterOptions o;
	o.noise = d.noise;
	const Eigen::Vector2d b = imu_grade_initial_bias_sigma(grade);
	o.prior.accel_bias_sigma = b[0];
	o.prior.gyro_bias_sigma = b[1];
	return o;
}
}  // namespace

TEST(InertialFilter, TracksNoiseFreeDataFromTheTrueState)
{
	InertialSimulationOptions s;
	s.duration = 20;
	s.imu_rate = 200;
	s.noise_free = true;
	const InertialDataset d = simulate_inertial(s);
	InertialInitialState init;
	init.x.R = d.truth[0].pose.getRotationMatrix().asEigen();
	init.x.p = position(d.truth[0].pose);
	init.x.v = d.truth[0].v;
	init.P = Eigen::Matrix<double, 15, 15>::Identity() * 1e-12;
	ErrorStateKalmanFilter f(d.noise, init);
	for (size_t k = 1; k < d.imu.size(); k++) f.propagate(d.imu[k - 1], d.imu[k]);
	EXPECT_LT((f.state().p - position(d.truth.back().pose)).norm(), 2e-3);
	EXPECT_LT(so3_log(f.state().R.transpose() * d.truth.back().pose.getRotationMatrix().asEigen()).norm(), 1e-5);
}

TEST(InertialFilter, FusionBeatsEachDeadReckoning)
{
	for (auto kind : {InertialTrajectoryKind::FigureEight, InertialTrajectoryKind::Car})
	{
		InertialSimulationOptions s;
		s.trajectory = kind;
		s.duration = 60;
		const InertialDataset d = simulate_inertial(s);
		const InertialInput in = input_of(d);
		InertialFilterOptions o = filter_options(d, s.grade);
		const double fused = rmse(run_inertial_filter(in, o), d, s.imu_rate);
		o.use_pose_priors = false;
		const double imu_odo = rmse(run_inertial_filter(in, o), d, s.imu_rate);
		o.use_odometry = false;
		const double imu_only = rmse(run_inertial_filter(in, o), d, s.imu_rate);
		const double odo_only = rmse(run_odometry_dead_reckoning(in, o.prior, inertial_report_times(in, o.keyframes)), d, s.imu_rate);
		std::printf("[eskf] %-8s APE RMSE: fused %.3f m, IMU+odometry %.3f m, IMU only %.3f m, odometry only %.3f m\n",
					enum_name(kind).c_str(), fused, imu_odo, imu_only, odo_only);
		EXPECT_LT(fused, 0.5 * 0.5);  // well below the priors' own 0.5 m per axis
		EXPECT_LT(fused, imu_only);
		EXPECT_LT(fused, odo_only);
	}
}

namespace
{
/** Average position NEES per report time over `runs` simulated runs, and the fraction of report times
 * inside the two-sided 95 % band of the average of `runs` χ²(3) variables. */
double nees_fraction_inside(int runs, bool use_odometry, double* mean_out)
{
	std::vector<double> sum;
	for (int r = 0; r < runs; r++)
	{
		InertialSimulationOptions s;
		s.duration = 30;
		s.seed = 100 + r;
		const InertialDataset d = simulate_inertial(s);
		InertialFilterOptions fo = filter_options(d, s.grade);
		fo.use_odometry = use_odometry;
		test::add_position_nees(sum, run_inertial_filter(input_of(d), fo), d, s.imu_rate);
	}
	const test::NeesBand b = test::nees_band(sum, runs);
	*mean_out = b.mean;
	std::printf("[eskf] position NEES over %d runs (%s): mean %.2f, band [%.2f, %.2f], %.0f %% of %zu steps inside\n",
				runs, use_odometry ? "priors + odometry" : "priors only", b.mean, b.lo, b.hi, 100.0 * b.inside,
				sum.size());
	return b.inside;
}
}  // namespace

TEST(InertialFilter, PositionNeesWithPosePriorsInsideTheBand)
{
	double mean = 0;
	EXPECT_GE(nees_fraction_inside(20, false, &mean), 0.9);
}

// With the lidar-like odometry fused: mean 3.19, 99 % of steps inside at this commit. (Measured 3.97 and 71 %
// when the test was written and disabled; not reproduced since. The simulated odometry noise is white per
// increment, as BetweenPoseFactor assumes: each increment is perturbed independently, the drift of the
// chained poses is their sum.)
TEST(InertialFilter, PositionNeesWithOdometryInsideTheBand)
{
	double mean = 0;
	EXPECT_GE(nees_fraction_inside(20, true, &mean), 0.9);
}
