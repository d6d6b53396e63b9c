// SlidingWindowOptions::eliminate_prior_only_landmarks: landmarks that only the marginal prior touches
// are held out of each LM solve (the solve sees the prior's marginal) and set to their conditional
// optimum afterwards. That must reach the same optimum as solving with every landmark in the problem.
#include <gtest/gtest.h>

#include "window_test_utils.h"
// The window's marginalisation unit is internal to swba_estimators; its header is included directly.
#include "../../modules/estimators/src/prior_only_elimination.h"

#include <algorithm>
#include <map>
#include <random>
#include <vector>

using namespace swba;
using namespace swba::estimators;

namespace
{
struct WindowRun
{
	eval::Trajectory online, lagged;
	std::map<std::int32_t, Eigen::Vector3d> landmarks;
	int prior_only_steps = 0, max_prior_only = 0;
};

WindowRun run_window(const io::Rawlog& log, bool eliminate)
{
	SlidingWindowOptions opt;
	opt.window_size = 10;
	opt.eliminate_prior_only_landmarks = eliminate;
	// Converge each step tightly, so both runs sit on the optimum of the same window problems.
	opt.solver.max_iterations = 50;
	opt.solver.function_tolerance = 1e-14;
	opt.solver.gradient_tolerance = 1e-12;
	opt.solver.parameter_tolerance = 1e-12;
	SlidingWindowEstimator est(opt);
	WindowRun r;
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
	const WindowRun full = run_window(log, false);
	const WindowRun elim = run_window(log, true);
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

// marginalize_leading (the window's marginalisation) against swba::marginalize (the reference with the
// eigen-decomposition and the pivoted LDLᵀ): the same prior, whether H* is positive definite (Cholesky
// square root) or rank-deficient like an inverse-depth anchor pose (LDLᵀ square root of the same H*).
namespace
{
void expect_same_prior(const Eigen::MatrixXd& H, const Eigen::VectorXd& b, int num_keep)
{
	const int n = static_cast<int>(H.rows());
	std::vector<int> keep, marg;
	for (int i = 0; i < n; i++) (i < num_keep ? keep : marg).push_back(i);
	const auto ref = swba::marginalize(H, b, keep, marg);
	const auto got = swba::estimators::detail::marginalize_leading(H, b, num_keep, 1e-12);
	const double scale = ref.H.norm();
	EXPECT_EQ(got.rank, ref.rank);
	EXPECT_LT((got.H - ref.H).norm(), 1e-10 * scale);
	EXPECT_LT((got.b - ref.b).norm(), 1e-10 * std::max(1.0, ref.b.norm()));
	// Same quadratic: JᵀJ = H* and Jᵀe = −b* (the square roots may differ by an orthogonal factor).
	EXPECT_LT((got.J.transpose() * got.J - ref.H).norm(), 1e-9 * scale);
	EXPECT_LT((got.J.transpose() * got.e + ref.b).norm(), 1e-9 * std::max(1.0, ref.b.norm()));
}
}  // namespace

TEST(MarginalizeLeading, EqualsReferenceMarginalisationForFullRankAndAnchorPoseDeficientPriors)
{
	std::mt19937 rng(11);
	std::normal_distribution<double> N(0, 1);
	// Full rank: 12 kept + 6 marginalised coordinates, H = AᵀA with more rows than columns.
	{
		Eigen::MatrixXd A(30, 18);
		for (int i = 0; i < A.rows(); i++)
			for (int j = 0; j < A.cols(); j++) A(i, j) = N(rng);
		Eigen::VectorXd b(18);
		for (int i = 0; i < 18; i++) b[i] = N(rng);
		expect_same_prior(A.transpose() * A, b, 12);
	}
	// Rank-deficient like an anchor pose a (6) with two landmarks (3 + 3) observed from the leaving
	// pose o (6, marginalised): each observation constrains only 3 combinations of (a, landmark, o),
	// so after eliminating o the prior over (a, l1, l2) has 12 − 6 = 6 null directions.
	{
		Eigen::MatrixXd A = Eigen::MatrixXd::Zero(6 + 6, 18);  // columns: a (0-5), l1 (6-8), l2 (9-11), o (12-17)
		for (int k = 0; k < 2; k++)
			for (int r = 0; r < 3; r++)
			{
				const int row = 3 * k + r;
				for (int j = 0; j < 6; j++) A(row, j) = N(rng);
				for (int j = 0; j < 3; j++) A(row, 6 + 3 * k + j) = N(rng);
				for (int j = 0; j < 6; j++) A(row, 12 + j) = N(rng);
			}
		for (int r = 6; r < 12; r++)  // odometry-like rows on o only
			A(r, 12 + (r - 6)) = 3.0;
		Eigen::VectorXd r(12);
		for (int i = 0; i < 12; i++) r[i] = N(rng);
		const Eigen::VectorXd b = A.transpose() * r;
		const Eigen::MatrixXd H = A.transpose() * A;
		const auto got = swba::estimators::detail::marginalize_leading(H, b, 12, 1e-12);
		EXPECT_EQ(got.rank, 6);
		expect_same_prior(H, b, 12);
	}
}
