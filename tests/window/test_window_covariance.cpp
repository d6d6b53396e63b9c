// The window's and the batch's marginal covariances against the dense inverse of the same
// information (the window's factor graph linearised at its values, FEJ as the solver sees it), for
// each gauge, on the first steps of kf-slam_6D_demo.
#include <gtest/gtest.h>
#include "support/dense_linearization.h"

#include "window_test_utils.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cstdio>

using namespace swba;
using namespace swba::estimators;

namespace
{
io::Rawlog first_steps(std::size_t n)
{
	io::Rawlog r = test::demo_rawlog();
	r.steps.resize(std::min(n, r.steps.size()));
	return r;
}

/** Σ of pose variable `v` from the dense inverse of the smoother's whole problem over its non-constant
 * variables (`held` treated as constant too). */
Eigen::MatrixXd dense_pose_covariance(const smoother::FixedLagSmoother& sm, VariableId v, VariableId held = -1)
{
	std::vector<VariableId> order;
	for (const auto& [id, var] : sm.problem().variables())
		if (!var.constant && id != held) order.push_back(id);
	const DenseLinearSystem sys = linearize_dense(sm.problem(), order);
	const Eigen::MatrixXd cov = sys.H.inverse();
	for (std::size_t k = 0; k < order.size(); k++)
		if (order[k] == v) return cov.block(sys.offsets[k], sys.offsets[k], 6, 6);
	return Eigen::MatrixXd::Zero(6, 6);
}

double rel(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) { return (a - b).norm() / b.norm(); }

SlidingWindowOptions options(GaugeMode gauge, int W)
{
	SlidingWindowOptions o;
	o.gauge = gauge;
	o.window_size = W;
	// After the solve, readings re-admitted by the gate and landmarks re-anchored for the marginalisation
	// change the information the dense reference sees: neither here.
	o.gate_readings = false;
	o.landmarks = LandmarkParameterization::Xyz;
	return o;
}

/** Under the free gauge, the initial pose (the problem's first variable; the tests keep it in the
 * window): the covariance is relative to it. Else none. */
VariableId held_pose(const SlidingWindowEstimator& est)
{
	return est.options().gauge == GaugeMode::Free ? est.smoother().problem().variables().begin()->first : -1;
}

/** Runs `steps` steps; after each, the online covariance of the newest pose against the dense inverse
 * of the window's information after that step (its marginalisation leaves that marginal unchanged);
 * after finish(), the lagged covariances of the poses flushed from the window. Returns the worst
 * relative error. */
double worst_window_error(const SlidingWindowOptions& o, std::size_t steps)
{
	const io::Rawlog rawlog = first_steps(steps);
	SlidingWindowEstimator est(o);
	double worst = 0;
	for (const auto& step : rawlog.steps)
	{
		est.process(step);
		const auto& sm = est.smoother();
		const Eigen::MatrixXd want = dense_pose_covariance(sm, sm.states().back().var, held_pose(est));
		EXPECT_EQ(est.online_covariances().size(), est.online_trajectory().size());
		worst = std::max(worst, rel(est.online_covariances().back(), want));
	}
	const auto& sm = est.smoother();
	std::vector<Eigen::MatrixXd> want;
	for (const auto& s : sm.states())
		if (s.time > 0.5) want.push_back(dense_pose_covariance(sm, s.var, held_pose(est)));
	est.finish();
	const auto& lagged = est.lagged_covariances();
	EXPECT_EQ(lagged.size(), est.lagged_trajectory().size());
	for (std::size_t i = 0; i < want.size(); i++)
		worst = std::max(worst, rel(lagged[lagged.size() - want.size() + i], want[i]));
	return worst;
}
}  // namespace

TEST(WindowCovariance, FixedGaugeEqualsDenseInverseOfTheWindowInformation)
{
	EXPECT_LT(worst_window_error(options(GaugeMode::Fixed, 4), 12), 1e-9);
}

TEST(WindowCovariance, PriorGaugeEqualsDenseInverseOfTheWindowInformation)
{
	EXPECT_LT(worst_window_error(options(GaugeMode::Prior, 4), 12), 1e-9);
}

TEST(WindowCovariance, FreeGaugeIsRelativeToTheInitialPoseWhileItIsInTheWindow)
{
	// The initial pose is the problem's first variable; W = 20 keeps it for the 10 steps.
	EXPECT_LT(worst_window_error(options(GaugeMode::Free, 20), 10), 1e-9);
}

TEST(WindowCovariance, FreeGaugeAfterTheInitialPoseLeftIsFiniteAndPositive)
{
	const io::Rawlog rawlog = first_steps(12);
	SlidingWindowEstimator est(options(GaugeMode::Free, 4));
	for (const auto& step : rawlog.steps) est.process(step);
	est.finish();
	for (std::size_t i = 0; i < est.lagged_covariances().size(); i++)
	{
		if (est.lagged_trajectory().stamps[i] < 0.5) continue;  // the initial pose (held while it was in)
		const PoseCovariance& c = est.lagged_covariances()[i];
		ASSERT_TRUE(c.allFinite());
		EXPECT_GT(Eigen::SelfAdjointEigenSolver<PoseCovariance>(c).eigenvalues().minCoeff(), 0);
	}
}

TEST(WindowCovariance, BatchEqualsTheUnboundedWindowAtTheSameOptimumForEachGauge)
{
	// Window W = ∞ solved tightly: its final covariances are the dense inverse's; the batch solves the
	// same problem (gate off: the same readings), so at the optimum it must agree with them.
	for (GaugeMode gauge : {GaugeMode::Fixed, GaugeMode::Prior, GaugeMode::Free})
	{
		SlidingWindowOptions o = options(gauge, 0);
		o.solver.function_tolerance = 1e-14;
		o.solver.max_iterations = 100;
		EXPECT_LT(worst_window_error(o, 10), 1e-9) << to_string(gauge);
		const io::Rawlog rawlog = first_steps(10);
		SlidingWindowEstimator est(o);
		for (const auto& step : rawlog.steps) est.process(step);
		est.finish();
		const BatchResult b = run_batch(rawlog, o);
		ASSERT_EQ(b.covariances.size(), b.trajectory.size());
		ASSERT_EQ(b.covariances.size(), est.lagged_covariances().size());  // W = ∞: the initial pose never leaves
		for (std::size_t i = 0; i < b.covariances.size(); i++)
			EXPECT_LT(rel(b.covariances[i], est.lagged_covariances()[i]), 1e-6) << to_string(gauge) << " pose " << i;
		EXPECT_FALSE(b.landmarks.empty());
		EXPECT_GT(b.covariance_seconds, 0);
	}
}

TEST(WindowCovariance, LandmarkWorldCovarianceDoesNotDependOnTheParameterisation)
{
	// The batch at its optimum, landmarks as inverse depth (world covariance through the anchor pose) and
	// as world points (their own block): the same problem in two charts, so the same covariance of each
	// landmark's world position. Fails when the anchor's part of the chain rule is wrong.
	SlidingWindowOptions o = options(GaugeMode::Fixed, 0);
	o.solver.function_tolerance = 1e-14;
	o.solver.max_iterations = 100;
	o.landmarks = LandmarkParameterization::InverseDepth;
	const io::Rawlog rawlog = first_steps(30);
	SlidingWindowOptions xyz = o;
	xyz.landmarks = LandmarkParameterization::Xyz;
	const BatchResult id = run_batch(rawlog, o), wp = run_batch(rawlog, xyz);
	ASSERT_EQ(id.landmarks.size(), wp.landmarks.size());
	ASSERT_FALSE(id.landmarks.empty());
	double worst = 0;
	for (const auto& [lid, e] : id.landmarks)
	{
		const auto& f = wp.landmarks.at(lid);
		EXPECT_LT((e.position - f.position).norm(), 1e-6) << "landmark " << lid;
		worst = std::max(worst, (e.covariance - f.covariance).norm() / f.covariance.norm());
	}
	std::printf("[covariance] landmark world covariance, inverse depth vs xyz: worst relative difference %.3g\n", worst);
	EXPECT_LT(worst, 1e-6);
}
