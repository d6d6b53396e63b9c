// FixedLagSmoother on linear-Gaussian problems, where marginalisation is exact: the fixed-lag estimate
// of the states still in the window, and their information, must equal the batch solution's. Runs the
// smoother's own machinery (update() with its marginalisation, the stored MarginalPrior and its factor).
#include <gtest/gtest.h>
#include "support/dense_linearization.h"
#include <swba/smoother/fixed_lag_smoother.h>

#include "linear_gaussian.h"
#include "smoother_test_client.h"

#include <Eigen/Dense>
#include <algorithm>
#include <memory>

using namespace swba;
using namespace swba::smoother;

namespace
{
/** The chain x0 … x(n−1) (2-D): a prior on x0, odometry-like steps and loops two states back. */
struct Chain
{
	std::vector<Eigen::Vector2d> guess;
	std::vector<std::pair<std::pair<int, int>, std::shared_ptr<test::LinearFactor>>> factors;  // (i, j), f
	std::shared_ptr<test::LinearFactor> prior;
};

Chain make_chain(int n)
{
	Chain c;
	for (int i = 0; i < n; i++) c.guess.emplace_back(0.9 * i + 0.05 * (i % 3), -0.1 * i);
	c.prior = std::make_shared<test::LinearFactor>(Eigen::MatrixXd::Identity(2, 2), Eigen::Vector2d(0.5, 0.1),
												   std::vector<int>{2});
	c.prior->set_sigma(0.1);
	for (int j = 1; j < n; j++)
	{
		c.factors.push_back(
			{{j - 1, j}, test::difference2(Eigen::Vector2d(1.0 + 0.1 * (j % 2), 0.2 * (j % 3) - 0.2), 0.2)});
		if (j >= 2) c.factors.push_back({{j - 2, j}, test::difference2(Eigen::Vector2d(2.05, 0.3 - 0.1 * j), 0.5)});
	}
	return c;
}

/** Options that converge each update() to rounding (the problems are linear). */
FixedLagSmootherOptions tight_options(int relinearized, int tail = 0)
{
	FixedLagSmootherOptions opt;
	opt.window = relinearized + tail;
	opt.relinearized = relinearized;
	opt.solver.max_iterations = 50;
	opt.solver.function_tolerance = opt.solver.gradient_tolerance = opt.solver.parameter_tolerance = 1e-14;
	return opt;
}

/** Adds state j of the chain with its factors to `sm` (x: the states so far) and updates it. */
void add_chain_state(FixedLagSmoother& sm, const Chain& c, std::vector<VariableId>& x, int j,
					 test::RecordingClient& client)
{
	x.push_back(sm.problem().add_variable(c.guess[j], euclidean_manifold(2)));
	sm.add_state(j, x.back());
	if (j == 0) sm.add_factor(c.prior, {x[0]});
	for (const auto& [ij, f] : c.factors)
		if (ij.second == j) sm.add_factor(f, {x[ij.first], x[j]});
	sm.update(client);
}
}  // namespace

TEST(FixedLagSmoother, LinearGaussianChainEqualsBatchAfterMarginalising)
{
	const int n = 9, lag = 3;
	const Chain c = make_chain(n);

	// Batch: every state and factor, solved exactly (one Gauss-Newton step on a linear problem).
	Problem batch;
	std::vector<VariableId> bx;
	for (const auto& g : c.guess) bx.push_back(batch.add_variable(g, euclidean_manifold(2)));
	batch.add_factor(c.prior, {bx[0]});
	for (const auto& [ij, f] : c.factors) batch.add_factor(f, {bx[ij.first], bx[ij.second]});
	const DenseLinearSystem full = linearize_dense(batch, bx);
	const Eigen::VectorXd x_batch = [&] {
		Eigen::VectorXd x(2 * n);
		for (int i = 0; i < n; i++) x.segment<2>(2 * i) = c.guess[i];
		return Eigen::VectorXd(x + full.H.ldlt().solve(full.b));
	}();
	const Eigen::MatrixXd cov_batch = full.H.inverse();

	// The smoother: one state at a time, update() (which marginalises the oldest once over the window).
	FixedLagSmoother sm(tight_options(lag));
	test::RecordingClient client;
	std::vector<VariableId> x;
	for (int j = 0; j < n; j++) add_chain_state(sm, c, x, j, client);
	ASSERT_EQ(client.marginalizations.size(), static_cast<std::size_t>(n - lag));
	ASSERT_EQ(client.left_states.size(), static_cast<std::size_t>(n - lag));
	ASSERT_TRUE(sm.prior().installed());

	// The states left in the window: the batch estimate, and the batch's marginal covariance.
	std::vector<VariableId> window;
	for (const auto& s : sm.states()) window.push_back(s.var);
	ASSERT_EQ(window.size(), static_cast<std::size_t>(lag));
	const int first = n - lag;
	for (int i = 0; i < lag; i++)
	{
		const Eigen::Vector2d xi = Eigen::Map<const Eigen::Vector2d>(sm.problem().value(window[i]));
		EXPECT_LT((xi - x_batch.segment<2>(2 * (first + i))).norm(), 1e-9) << "state " << first + i;
	}
	const DenseLinearSystem reduced = linearize_dense(sm.problem(), window);
	const Eigen::MatrixXd cov_window = reduced.H.inverse();
	const Eigen::MatrixXd cov_ref = cov_batch.bottomRightCorner(2 * lag, 2 * lag);
	EXPECT_LT((cov_window - cov_ref).norm(), 1e-9 * cov_ref.norm());
	// The batch optimum is the optimum of the window problem: its gradient vanishes there.
	EXPECT_LT(reduced.b.norm(), 1e-6);
}

// The linear tail: 2 re-linearised states and a tail of 4: the states that left them are smoothed by
// back-substitution of the conditionals they left with. On a linear-Gaussian chain (loops two states
// back, so a separator holds two states) every smoothed state must be the batch estimate of the
// history so far, at every step, and a state leaves the smoother at the window (6) with that estimate.
TEST(FixedLagSmoother, LinearTailStatesAreTheBatchEstimatesOfTheHistorySoFar)
{
	const int n = 12, relinearized = 2, tail = 4;
	const Chain c = make_chain(n);
	const FixedLagSmootherOptions opt = tight_options(relinearized, tail);
	FixedLagSmoother sm(opt);
	test::RecordingClient client;
	std::vector<VariableId> x;
	for (int j = 0; j < n; j++)
	{
		add_chain_state(sm, c, x, j, client);

		// The batch of states 0 … j.
		Problem batch;
		std::vector<VariableId> bx;
		for (int i = 0; i <= j; i++) bx.push_back(batch.add_variable(c.guess[i], euclidean_manifold(2)));
		batch.add_factor(c.prior, {bx[0]});
		for (const auto& [ij, f] : c.factors)
			if (ij.second <= j) batch.add_factor(f, {bx[ij.first], bx[ij.second]});
		const DenseLinearSystem full = linearize_dense(batch, bx);
		const Eigen::VectorXd dx = full.H.ldlt().solve(full.b);
		const auto batch_at = [&](double t) {
			const int i = static_cast<int>(t);
			return Eigen::Vector2d(c.guess[i] + dx.segment<2>(2 * i));
		};
		for (const LinearState& s : sm.linear_states())
			EXPECT_LT((Eigen::Map<const Eigen::Vector2d>(s.value.data()) - batch_at(s.time)).norm(), 1e-9)
				<< "state " << s.time << " at step " << j;

		// A state leaves the smoother at the window (relinearized + tail) with the estimate it had.
		if (j >= relinearized + tail)
		{
			ASSERT_EQ(client.left_states.size(), static_cast<std::size_t>(j + 1 - relinearized - tail));
			const LinearState& s = client.left_states.back();
			EXPECT_EQ(s.time, j - relinearized - tail);
			EXPECT_LT((Eigen::Map<const Eigen::Vector2d>(s.value.data()) - batch_at(s.time)).norm(), 1e-9);
		}
		EXPECT_EQ(sm.linear_states().size(), static_cast<std::size_t>(std::clamp(j + 1 - relinearized, 0, tail)));
	}
	EXPECT_EQ(client.left_states.size(), static_cast<std::size_t>(n - relinearized - tail));
}

namespace
{
/** A linear-Gaussian run for the tail's change of variables: 6-D states (a prior on the first,
 * differences between neighbours) and two 3-D landmarks observed as l − (first three coordinates of
 * the state): l by the first four states only, so that it is left to the prior, m by every state, so
 * that new readings keep moving the old estimates (and l) after l left the window. */
struct LandmarkRun
{
	static constexpr int kSteps = 12, kLastObservation = 3;
	std::shared_ptr<test::LinearFactor> prior, odometry(int t) const, observation(int t) const;
	LandmarkRun()
	{
		prior = std::make_shared<test::LinearFactor>(Eigen::MatrixXd::Identity(6, 6), Eigen::VectorXd::Zero(6),
													 std::vector<int>{6});
		prior->set_sigma(0.05);
	}
	static Eigen::VectorXd state_guess(int t) { return Eigen::VectorXd::LinSpaced(6, 0.1 * t, 0.3 * t + 0.2); }
};

std::shared_ptr<test::LinearFactor> LandmarkRun::odometry(int t) const
{
	Eigen::MatrixXd A(6, 12);
	A << -Eigen::MatrixXd::Identity(6, 6), Eigen::MatrixXd::Identity(6, 6);
	Eigen::VectorXd d = Eigen::VectorXd::LinSpaced(6, 0.1, 0.3) + 0.02 * Eigen::VectorXd::Constant(6, t % 3);
	auto f = std::make_shared<test::LinearFactor>(A, d, std::vector<int>{6, 6});
	f->set_sigma(0.1);
	return f;
}

std::shared_ptr<test::LinearFactor> LandmarkRun::observation(int t) const
{
	Eigen::MatrixXd A = Eigen::MatrixXd::Zero(3, 9);
	A.leftCols(3) = -Eigen::Matrix3d::Identity();
	A.rightCols(3) = Eigen::Matrix3d::Identity();
	auto f = std::make_shared<test::LinearFactor>(A, Eigen::Vector3d(2.0 + 0.01 * t, -1.0, 0.5 - 0.02 * t),
												  std::vector<int>{6, 3});
	f->set_sigma(0.03);
	return f;
}
}  // namespace

// A change of variables of a prior variable (l = A l' + B y, linear here, so the change is exact) must
// leave every estimate as it was, the linear tail's included: the conditionals that hold l are
// rewritten over l' and y. Two smoothers on the same data, one of them changing variables mid-run; with
// first-estimate Jacobians off the conditionals hold l at other points than the prior does.
class LinearTailChange : public ::testing::TestWithParam<bool>
{
};

TEST_P(LinearTailChange, FollowsAChangeOfVariablesOfThePrior)
{
	const LandmarkRun run;
	const int change_at = 7;
	FixedLagSmootherOptions opt = tight_options(2, 4);
	opt.first_estimate_jacobians = GetParam();
	FixedLagSmoother ref(opt), changed(opt);
	test::RecordingClient client;
	std::vector<VariableId> xr, xc;
	const Eigen::Vector3d l0(2.5, 0.0, 1.0);
	const VariableId lr = ref.problem().add_variable(l0, euclidean_manifold(3));
	VariableId lc = changed.problem().add_variable(l0, euclidean_manifold(3));
	const Eigen::Vector3d m0(-1.0, 2.0, 0.0);
	const VariableId mr = ref.problem().add_variable(m0, euclidean_manifold(3));
	const VariableId mc = changed.problem().add_variable(m0, euclidean_manifold(3));
	const Eigen::Matrix3d D = Eigen::Vector3d(1.0, 2.0, 0.5).asDiagonal();
	Eigen::Matrix3d H_new;
	H_new << 1.0, 0.2, 0.0, -0.1, 1.0, 0.3, 0.0, 0.1, 0.8;
	Eigen::Matrix<double, 3, 6> H_y = Eigen::Matrix<double, 3, 6>::Zero();
	H_y(0, 0) = 0.5;
	H_y(1, 4) = -0.25;
	H_y(2, 2) = 0.1;
	const Eigen::Matrix3d A = D * H_new;
	int changes = 0;
	for (int t = 0; t < LandmarkRun::kSteps; t++)
	{
		for (auto* sm : {&ref, &changed})
		{
			auto& x = sm == &ref ? xr : xc;
			const VariableId l = sm == &ref ? lr : lc;
			x.push_back(sm->problem().add_variable(LandmarkRun::state_guess(t), euclidean_manifold(6)));
			sm->add_state(t, x.back());
			if (t == 0) sm->add_factor(run.prior, {x[0]});
			if (t > 0) sm->add_factor(run.odometry(t), {x[t - 1], x[t]});
			if (t <= LandmarkRun::kLastObservation) sm->add_factor(run.observation(t), {x[t], l});
			sm->add_factor(run.observation(3 * t + 1), {x[t], sm == &ref ? mr : mc});
			sm->update(client);
		}
		if (t == change_at)
		{
			// l = A l' + B y with y the newest state, around the prior's points: l_lin = A l'_lin + B y_lin.
			ASSERT_TRUE(changed.prior().index_of(lc) >= 0);
			const VariableId y = xc[t];
			const Eigen::Vector3d l_now = Eigen::Map<const Eigen::Vector3d>(changed.problem().value(lc));
			const Eigen::Map<const Eigen::Matrix<double, 6, 1>> y_now(changed.problem().value(y));
			const Eigen::Vector3d lp_now = A.lu().solve(l_now - D * H_y * y_now);
			const VariableId lp = changed.problem().add_variable(lp_now, euclidean_manifold(3));
			const bool applied = changed.change_prior_variable(lc, {y}, [&](const PriorPoints& lin) {
				const Eigen::Map<const Eigen::Vector3d> l_lin(lin.old_lin.data());
				const Eigen::Map<const Eigen::Matrix<double, 6, 1>> y_lin(lin.others_lin[0].data());
				const Eigen::Vector3d lp_lin = A.lu().solve(l_lin - D * H_y * y_lin);
				const std::vector<double> lp_lin_v(lp_lin.data(), lp_lin.data() + 3);
				return VariableChange{lc, lp, lp_lin_v, lp_lin_v, D, H_new, {{y, H_y}}};
			});
			ASSERT_TRUE(applied);
			changed.problem().remove_variable(lc);
			lc = lp;
			changes++;
			continue;  // the tail follows the change at the next update()
		}
		const auto a = ref.linear_states(), b = changed.linear_states();
		ASSERT_EQ(a.size(), b.size());
		for (std::size_t i = 0; i < a.size(); i++)
			EXPECT_LT((Eigen::Map<const Eigen::VectorXd>(a[i].value.data(), 6) -
					   Eigen::Map<const Eigen::VectorXd>(b[i].value.data(), 6))
						  .norm(),
					  1e-7)  // the two converge along different LM paths: ≈ 1e-9 apart; a wrong change is ≥ 1e-4 off
				<< "state " << a[i].time << " at step " << t;
	}
	EXPECT_EQ(changes, 1);
	EXPECT_EQ(ref.linear_states().size(), 4u);
}

INSTANTIATE_TEST_SUITE_P(FixedLagSmoother, LinearTailChange, ::testing::Values(true, false),
						 [](const auto& p) { return p.param ? "Fej" : "NoFej"; });

// The three-state chain x1 − x2 − x3 (σ = 0.1 between x1 and x2, a prior on x2 with σ = 0.2, σ = 0.3
// between x2 and x3; linear, scalar) with its printed normal equations and the printed prior after
// marginalising x2 through the smoother: [[26.5306, −8.16327], [−8.16327, 10.2041]] over (x1, x3).
TEST(FixedLagSmoother, MarginalisingTheMiddleOfAThreeStateChainGivesThePrintedPrior)
{
	FixedLagSmootherOptions opt;
	opt.window = 2;
	FixedLagSmoother sm(opt);
	Problem& p = sm.problem();
	const VariableId x2 = p.add_variable(Eigen::VectorXd::Constant(1, 0.3), euclidean_manifold(1));
	const VariableId x1 = p.add_variable(Eigen::VectorXd::Constant(1, -0.2), euclidean_manifold(1));
	const VariableId x3 = p.add_variable(Eigen::VectorXd::Constant(1, 0.7), euclidean_manifold(1));
	for (VariableId v : {x2, x1, x3}) sm.add_state(0, v);
	auto between = [](double sigma) {
		auto f = std::make_shared<test::LinearFactor>(Eigen::RowVector2d(-1, 1), Eigen::VectorXd::Constant(1, 0.1),
													  std::vector<int>{1, 1});
		f->set_sigma(sigma);
		return f;
	};
	auto prior = std::make_shared<test::LinearFactor>(Eigen::MatrixXd::Identity(1, 1), Eigen::VectorXd::Zero(1),
													  std::vector<int>{1});
	prior->set_sigma(0.2);
	sm.add_factor(between(0.1), {x1, x2});
	sm.add_factor(prior, {x2});
	sm.add_factor(between(0.3), {x2, x3});

	const DenseLinearSystem before = linearize_dense(p, {x1, x2, x3});
	EXPECT_NEAR(before.H(0, 0), 100, 5e-4);
	EXPECT_NEAR(before.H(1, 1), 136.111, 5e-4);
	EXPECT_NEAR(before.H(1, 2), -11.1111, 5e-5);
	EXPECT_NEAR(before.H(2, 2), 11.1111, 5e-5);

	test::RecordingClient client;
	const UpdateSummary u = sm.update(client);  // three states in a window of two: x2 leaves
	ASSERT_TRUE(u.marginalization);
	const MarginalizationSummary& m = *u.marginalization;
	EXPECT_EQ(m.removed.size(), 3u);
	EXPECT_EQ(m.unevaluable_factors, 0);
	ASSERT_EQ(sm.prior().variables(), (std::vector<VariableId>{x1, x3}));
	const Eigen::MatrixXd& H = sm.prior().H();
	EXPECT_NEAR(H(0, 0), 26.5306, 5e-5);
	EXPECT_NEAR(H(0, 1), -8.16327, 5e-6);
	EXPECT_NEAR(H(1, 0), -8.16327, 5e-6);
	EXPECT_NEAR(H(1, 1), 10.2041, 5e-5);
	// The prior's factor in the problem is that quadratic.
	const DenseLinearSystem after = linearize_dense(p, {x1, x3});
	EXPECT_LT((after.H - H).norm(), 1e-9 * H.norm());
}

// A factor whose residual is undefined at the current values cannot enter the marginal prior: it is
// counted, not silently dropped.
TEST(FixedLagSmoother, MarginalisationCountsFactorsItCannotEvaluate)
{
	class Undefined final : public Factor
	{
	   public:
		Undefined() : Factor(1, {1, 1}) {}
		bool evaluate(const double* const*, double*, double* const*) const override { return false; }
	};
	FixedLagSmootherOptions opt;
	opt.window = 1 + 1;
	FixedLagSmoother sm(opt);
	Problem& p = sm.problem();
	std::vector<VariableId> x;
	for (int i = 0; i < 3; i++)
	{
		x.push_back(p.add_variable(Eigen::VectorXd::Constant(1, i), euclidean_manifold(1)));
		sm.add_state(i, x.back());
	}
	auto f = std::make_shared<test::LinearFactor>(Eigen::RowVector2d(-1, 1), Eigen::VectorXd::Constant(1, 1.0),
												  std::vector<int>{1, 1});
	sm.add_factor(f, {x[0], x[1]});
	sm.add_factor(std::make_shared<Undefined>(), {x[0], x[2]});
	test::RecordingClient client;
	const UpdateSummary u = sm.update(client);
	ASSERT_TRUE(u.marginalization);
	const MarginalizationSummary& m = *u.marginalization;
	EXPECT_EQ(m.removed.size(), 2u);
	EXPECT_EQ(m.unevaluable_factors, 1);
}

// Covariances from update() on the linear-Gaussian chain: at every step, the newest state's and the
// oldest state's (about to leave) marginal covariance must be the exact marginal given the factors so
// far, i.e. the block of the dense inverse of the full-history information (marginalisation is exact).
TEST(FixedLagSmoother, UpdateCovariancesAreTheExactMarginalsOfALinearGaussianChain)
{
	const int n = 9, lag = 3;
	const Chain c = make_chain(n);
	FixedLagSmootherOptions opt;
	opt.window = lag;
	opt.solver.max_iterations = 50;
	FixedLagSmoother sm(opt);
	test::RecordingClient client;
	std::vector<VariableId> x;
	double worst = 0;
	for (int j = 0; j < n; j++)
	{
		x.push_back(sm.problem().add_variable(c.guess[j], euclidean_manifold(2)));
		sm.add_state(j, x.back());
		if (j == 0) sm.add_factor(c.prior, {x[0]});
		for (const auto& [ij, f] : c.factors)
			if (ij.second == j) sm.add_factor(f, {x[ij.first], x[j]});
		CovarianceRequest request;
		request.groups = {{x[j]}, {sm.states().front().var}};
		const UpdateSummary u = sm.update(client, request);
		ASSERT_TRUE(u.covariance.ok) << u.covariance.message;
		// The exact marginal: states 0..j with every factor so far.
		Problem full;
		std::vector<VariableId> fx;
		for (int i = 0; i <= j; i++) fx.push_back(full.add_variable(c.guess[i], euclidean_manifold(2)));
		full.add_factor(c.prior, {fx[0]});
		for (const auto& [ij, f] : c.factors)
			if (ij.second <= j) full.add_factor(f, {fx[ij.first], fx[ij.second]});
		const Eigen::MatrixXd cov = linearize_dense(full, fx).H.inverse();
		const int oldest = std::max(0, j - lag);
		const Eigen::MatrixXd want_new = cov.block(2 * j, 2 * j, 2, 2);
		const Eigen::MatrixXd want_old = cov.block(2 * oldest, 2 * oldest, 2, 2);
		worst = std::max(worst, (u.covariance.blocks[0] - want_new).norm() / want_new.norm());
		worst = std::max(worst, (u.covariance.blocks[1] - want_old).norm() / want_old.norm());
	}
	EXPECT_LT(worst, 1e-9);
}
