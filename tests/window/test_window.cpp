// Sliding-window estimator: equivalence with batch without marginalisation, FEJ keeps the prior free of
// information along the gauge directions, invalid options. (The marginalisation itself on a
// linear-Gaussian chain, where it is exact: tests/smoother/test_fixed_lag_smoother.cpp.)
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "window_test_utils.h"

using namespace swba;
using namespace swba::estimators;

namespace
{

io::Rawlog first_steps(const io::Rawlog& r, std::size_t n)
{
	io::Rawlog out = r;
	out.steps.resize(std::min(n, r.steps.size()));
	return out;
}

}  // namespace

namespace
{
/** Largest translation difference between the window's final estimates of the poses still in it (the
 * last W + 1; they have seen every measurement, the older ones through the prior) and the batch
 * solution, over the first `steps` steps of the demo, both converged tightly. */
double window_vs_batch(std::size_t steps, int W, std::size_t* marginalised)
{
	const auto rawlog = first_steps(test::demo_rawlog(), steps);
	SlidingWindowOptions opt;
	opt.window_size = W;
	opt.relinearized_poses = 0;  // every window pose re-linearised: the window is the batch problem
	// Least squares: the batch solve starts from dead reckoning, the window from its warm starts; with the
	// Cauchy loss (the default) the two converge to the same optimum only to the solvers' tolerance.
	opt.robust_loss = RobustLoss::None;
	opt.solver.function_tolerance = 1e-14;
	opt.solver.max_iterations = 30;
	SlidingWindowEstimator est(opt);
	*marginalised = 0;
	for (const auto& s : rawlog.steps) *marginalised += est.process(s).prior_rank > 0;
	est.finish();
	const auto batch = run_batch(rawlog, opt, 100);
	const auto& lag = est.lagged_trajectory();
	// The lagged trajectory also holds the initial pose (t = 0) once it left the window; batch does not.
	const std::size_t skip = lag.size() - batch.trajectory.size();
	EXPECT_EQ(lag.size(), batch.trajectory.size() + (*marginalised > 0 ? 1 : 0));
	double worst = 0;
	const std::size_t in_window = std::min<std::size_t>(W + 1, batch.trajectory.size());
	for (std::size_t i = batch.trajectory.size() - in_window; i < batch.trajectory.size(); i++)
	{
		EXPECT_EQ(lag.stamps[i + skip], batch.trajectory.stamps[i]);
		worst = std::max(worst, (lag.poses[i + skip].translation() - batch.trajectory.poses[i].translation()).norm());
	}
	return worst;
}
}  // namespace

// With W ≥ the number of steps nothing is marginalised: the window's final estimate is the batch
// solution (the smoother without its marginalisation).
TEST(SlidingWindow, WindowLargerThanRunEqualsBatch)
{
	std::size_t marginalised = 0;
	const double d = window_vs_batch(60, 100, &marginalised);
	EXPECT_EQ(marginalised, 0u);
	EXPECT_LT(d, 1e-6);
}

// With marginalisation the window's final estimate of its poses differs from batch only by the
// linearisation of the marginalised factors at their first estimates.
TEST(SlidingWindow, WindowWithMarginalisationStaysCloseToBatch)
{
	std::size_t marginalised = 0;
	const double d = window_vs_batch(60, 10, &marginalised);
	std::cout << "[window vs batch] 60 steps, W = 10: max |Δt| of the poses in the final window " << d << " m\n";
	EXPECT_GT(marginalised, 40u);
	EXPECT_LT(d, 1e-3);
}

TEST(SlidingWindow, RejectsInvalidOptions)
{
	SlidingWindowOptions opt;
	opt.window_size = 1;
	EXPECT_THROW(SlidingWindowEstimator{opt}, std::invalid_argument);
	opt.window_size = 10;
	opt.gauge_prior_weight = -1;
	EXPECT_THROW(SlidingWindowEstimator{opt}, std::invalid_argument);
	EXPECT_THROW(parse_landmark_policy("fast"), std::invalid_argument);
	EXPECT_THROW(parse_gauge_mode("loose"), std::invalid_argument);
}
