// The inertial sliding window on simulated data: agreement with the filter on a short near-linear case,
// and its accuracy against the filter, the full-history optimum and the batch solution.
#include <swba/core/lie.h>
#include <swba/estimators/inertial_window.h>
#include <swba/problems/inertial_simulation.h>

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cmath>

using namespace swba;
using namespace swba::estimators;
using namespace swba::problems;

namespace
{
Eigen::Vector3d position(const mrpt::poses::CPose3D& p) { return {p.x(), p.y(), p.z()}; }

InertialInput input_of(const InertialDataset& d)
{
	InertialInput in;
	in.imu = d.imu;
	for (const auto& z : d.pose_priors) in.pose_priors.push_back({z.t, "MAP", z.pose, z.covariance});
	for (const auto& z : d.odometry) in.odometry.push_back({z.t, "ODO", z.pose, z.covariance});
	return in;
}

double rmse(const InertialTrajectory& tr, const InertialDataset& d, double rate)
{
	double s = 0;
	for (size_t i = 0; i < tr.t.size(); i++)
		s += (position(tr.poses[i]) - position(d.truth.at(std::lround(tr.t[i] * rate)).pose)).squaredNorm();
	return std::sqrt(s / tr.t.size());
}

InertialWindowOptions window_options(const InertialDataset& d, ImuGrade grade, int w)
{
	InertialWindowOptions o;
	o.window_size = w;
	o.measurements.noise = d.noise;
	const Eigen::Vector2d b = imu_grade_initial_bias_sigma(grade);
	o.measurements.prior.accel_bias_sigma = b[0];
	o.measurements.prior.gyro_bias_sigma = b[1];
	return o;
}
}  // namespace

TEST(InertialWindow, AgreesWithTheFilterOnAShortNearLinearCase)
{
	// Tactical IMU, priors only, 5 s: the full-history window's newest state is the filter's estimate up to
	// linearisation; the difference must be far below the estimate's own uncertainty.
	InertialSimulationOptions s;
	s.grade = ImuGrade::Tactical;
	s.duration = 5;
	const InertialDataset d = simulate_inertial(s);
	const InertialInput in = input_of(d);
	InertialWindowOptions o = window_options(d, s.grade, 0);
	o.measurements.use_odometry = false;  // the odometry gives the initial velocity only
	const InertialTrajectory f = run_inertial_filter(in, o.measurements);
	const InertialWindowResult w = run_inertial_window(in, o);
	ASSERT_EQ(f.t.size(), w.online.t.size());
	double worst = 0;
	for (size_t i = 0; i < f.t.size(); i++)
	{
		const Eigen::Vector3d e = position(f.poses[i] - w.online.poses[i]);
		worst = std::max(worst, std::sqrt(e.dot(f.pose_covariances[i].topLeftCorner<3, 3>().ldlt().solve(e))));
		EXPECT_LT(so3_log((f.poses[i] - w.online.poses[i]).getRotationMatrix().asEigen()).norm(), 1e-3);
	}
	std::printf("[window] vs filter: worst Mahalanobis position difference %.3g sigma\n", worst);
	EXPECT_LT(worst, 0.1);
}

TEST(InertialWindow, OnlineMatchesTheFilterAndSmoothingImprovesOnIt)
{
	// The tactical grade's bias random walk makes rows of information ~1e15 next to pose priors of ~4:
	// a marginalisation threshold relative to the largest pivot must not cut the latter.
	const std::pair<InertialTrajectoryKind, ImuGrade> cases[] = {{InertialTrajectoryKind::FigureEight, ImuGrade::Consumer},
																  {InertialTrajectoryKind::Car, ImuGrade::Consumer},
																  {InertialTrajectoryKind::FigureEight, ImuGrade::Tactical}};
	for (const auto& [kind, grade] : cases)
	{
		InertialSimulationOptions s;
		s.trajectory = kind;
		s.grade = grade;
		s.duration = 30;
		const InertialDataset d = simulate_inertial(s);
		const InertialInput in = input_of(d);
		const double eskf = rmse(run_inertial_filter(in, window_options(d, s.grade, 10).measurements), d, s.imu_rate);
		const double batch = rmse(run_inertial_batch(in, window_options(d, s.grade, 10)), d, s.imu_rate);
		const InertialWindowResult w10 = run_inertial_window(in, window_options(d, s.grade, 10));
		const InertialWindowResult w30 = run_inertial_window(in, window_options(d, s.grade, 30));
		const double on10 = rmse(w10.online, d, s.imu_rate), lag10 = rmse(w10.lagged, d, s.imu_rate),
					 lag30 = rmse(w30.lagged, d, s.imu_rate);
		std::printf("[window] %-8s %-8s ESKF %.4f, W=10 online %.4f lagged %.4f, W=30 lagged %.4f, batch %.4f m\n",
					enum_name(kind).c_str(), enum_name(grade).c_str(), eskf, on10, lag10, lag30, batch);
		EXPECT_LE(on10, 1.01 * eskf);  // the online window is the causal estimate, as the filter
		EXPECT_LT(lag10, on10);		   // smoothing over the window helps...
		EXPECT_LT(lag30, lag10);	   // ...the more, the longer the window
		EXPECT_LT(batch, lag30);	   // and the batch solution uses everything
		EXPECT_GT(w10.relative_factors, 0u);
	}
}
