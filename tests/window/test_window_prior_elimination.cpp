// SlidingWindowOptions::eliminate_prior_only_landmarks: landmarks that only the marginal prior touches
// are held out of each LM solve (the solve sees the prior's marginal) and set to their conditional
// optimum afterwards. That must reach the same optimum as solving with every landmark in the problem.
#include <gtest/gtest.h>

#include "window_test_utils.h"

#include <algorithm>
#include <map>
#include <vector>

using namespace swba;
using namespace swba::estimators;

namespace
{
struct EliminationRun
{
	eval::Trajectory online, lagged;
	std::map<std::int32_t, Eigen::Vector3d> landmarks;
	int prior_only_steps = 0, max_prior_only = 0;
};

EliminationRun run_eliminating(const io::Rawlog& log, bool eliminate)
{
	SlidingWindowOptions opt;
	opt.window_size = 10;
	// The elimination on the whole window re-linearised; the linear tail's exactness is tested in
	// tests/smoother (with a tail the two runs' LM paths part by ~1e-6 m more).
	opt.relinearized_poses = 0;
	opt.eliminate_prior_only_landmarks = eliminate;
	// Converge each step tightly, so both runs sit on the optimum of the same window problems.
	opt.solver.max_iterations = 50;
	opt.solver.function_tolerance = 1e-14;
	opt.solver.gradient_tolerance = 1e-12;
	opt.solver.parameter_tolerance = 1e-12;
	SlidingWindowEstimator est(opt);
	EliminationRun r;
	for (const auto& s : log.steps)
	{
		const StepSummary& sum = est.process(s);

		if (sum.prior_only_landmarks > 0) r.prior_only_steps++;
		r.max_prior_only = std::max(r.max_prior_only, sum.prior_only_landmarks);
	}
	r.landmarks = est.landmarks();
	est.finish();
	r.online = est.online_trajectory();
	r.lagged = est.lagged_trajectory();
	return r;
}

/** Per-pose translation differences between two trajectories of the same stamps, sorted. */
std::vector<double> translation_differences(const eval::Trajectory& a, const eval::Trajectory& b)
{
	EXPECT_EQ(a.size(), b.size());
	std::vector<double> d;
	for (std::size_t i = 0; i < std::min(a.size(), b.size()); i++)
	{
		EXPECT_EQ(a.stamps[i], b.stamps[i]);
		d.push_back((a.poses[i].translation() - b.poses[i].translation()).norm());
	}
	std::sort(d.begin(), d.end());
	return d;
}
}  // namespace

TEST(SlidingWindowPriorElimination, SameOptimumAsSolvingWithEveryLandmark)
{
	io::RawlogReaderOptions ro;
	ro.max_steps = 150;
	const io::Rawlog log = io::read_rawlog(test::dataset("kf-slam_6D_demo.rawlog"), ro);
	const EliminationRun full = run_eliminating(log, false);
	const EliminationRun elim = run_eliminating(log, true);
	// The elimination is exercised (landmarks leave the window's view and stay in the prior) and off
	// when disabled.
	EXPECT_GT(elim.prior_only_steps, 50);
	EXPECT_GE(elim.max_prior_only, 5);
	EXPECT_EQ(full.prior_only_steps, 0);
	// Same optimum: the online/lagged poses are ~1 cm from the truth; the two runs agree to ~1e-7 m at
	// most steps. At a few ill-conditioned steps LM stops (on its tolerances, at up to ~25 iterations in
	// both runs) a fraction of a millimetre apart along a flat direction of the same cost (final costs
	// equal to 1e-6 relative), so the maximum is bounded by 1 mm, the median by 1e-6 m.
	for (const auto* which : {&full.online, &full.lagged})
	{
		const auto d = translation_differences(*which, which == &full.online ? elim.online : elim.lagged);
		ASSERT_FALSE(d.empty());
		EXPECT_LT(d[d.size() / 2], 1e-6);
		EXPECT_LT(d.back(), 1e-3);
		std::cout << "[prior elimination] " << (which == &full.online ? "online" : "lagged") << " |Δt| median "
				  << d[d.size() / 2] << " m, max " << d.back() << " m\n";
	}
	ASSERT_EQ(full.landmarks.size(), elim.landmarks.size());
	double d_map = 0;
	for (const auto& [id, p] : full.landmarks)
	{
		ASSERT_TRUE(elim.landmarks.count(id)) << id;
		d_map = std::max(d_map, (p - elim.landmarks.at(id)).norm());
	}
	EXPECT_LT(d_map, 1e-6);
	std::cout << "[prior elimination] map max |Δp| " << d_map << " m; up to " << elim.max_prior_only
			  << " landmarks held out of a solve\n";
}
