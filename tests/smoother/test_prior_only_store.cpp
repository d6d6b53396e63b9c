// PriorOnly::Store on a linear-Gaussian SLAM-like problem, where the fixed-lag
// estimate is exact: 2-D states in a chain and 2-D "landmarks" that each state observes by l − x = z.
// Landmarks leave the window's view (stored as their conditional), some return (released into the
// prior), one never does. At every step the window's states and every landmark (stored ones at their
// conditional mean) must equal the batch solution over the data so far, and at the end the covariance
// over the window and every landmark must equal the batch's marginal. On the same data with a linear
// tail: the covariance of the tail's states (the lagged covariance) with each prior-only handling.
#include <gtest/gtest.h>
#include "support/dense_linearization.h"
#include <swba/smoother/fixed_lag_smoother.h>

#include "linear_gaussian.h"
#include "smoother_test_client.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cstdio>
#include <map>
#include <memory>
#include <set>

using namespace swba;
using namespace swba::smoother;

namespace
{
/** The states observing each landmark: leaving and returning while the window slides. */
const std::map<int, std::set<int>> kSeenBy = {
	{0, {0, 1, 2, 3, 13, 14, 15}}, {1, {2, 3, 4, 5, 6}},   {2, {4, 5, 6, 7, 8, 9, 16}},
	{3, {7, 8, 9, 10, 11}},        {4, {0, 1, 2}},         {5, {9, 10, 11, 12, 13, 14, 15, 16, 17}},
	{6, {3, 4, 5, 6, 15}}};  // leaves with 1 (both stored at once), returns without it
constexpr int kStates = 18, kLag = 3, kLandmarks = 7;

Eigen::Vector2d state_truth(int j) { return {0.8 * j, 0.3 * std::sin(0.7 * j)}; }
Eigen::Vector2d landmark_truth(int i) { return {2.0 * i - 1.0, 1.5 - 0.4 * i}; }
/** A deterministic "noise" so the data disagree with each other. */
Eigen::Vector2d wiggle(int a, int b) { return {0.03 * std::sin(1.3 * a + 0.7 * b), 0.02 * std::cos(0.9 * a - 1.1 * b)}; }

struct Data
{
	std::vector<std::pair<std::pair<int, int>, std::shared_ptr<test::LinearFactor>>> odometry;  // (j−1, j)
	std::vector<std::pair<std::pair<int, int>, std::shared_ptr<test::LinearFactor>>> readings;  // (j, landmark)
	std::shared_ptr<test::LinearFactor> prior;
};

Data make_data()
{
	Data d;
	d.prior = std::make_shared<test::LinearFactor>(Eigen::MatrixXd::Identity(2, 2), state_truth(0), std::vector<int>{2});
	d.prior->set_sigma(0.01);
	for (int j = 1; j < kStates; j++)
		d.odometry.push_back({{j - 1, j}, test::difference2(state_truth(j) - state_truth(j - 1) + wiggle(j, 0), 0.1)});
	for (const auto& [i, states] : kSeenBy)
		for (int j : states)
			d.readings.push_back({{j, i}, test::difference2(landmark_truth(i) - state_truth(j) + wiggle(j, i + 1), 0.05)});
	return d;
}

/** The batch over states 0..j and the readings so far: solution and covariance over (states, landmarks seen). */
struct Batch
{
	std::map<int, Eigen::Vector2d> state, landmark;
	Eigen::MatrixXd cov;  ///< over states 0..j then the landmarks seen, in id order
	std::vector<int> landmark_order;
};

Batch solve_batch(const Data& d, int j)
{
	Problem p;
	std::vector<VariableId> xs;
	std::map<int, VariableId> ls;
	for (int s = 0; s <= j; s++) xs.push_back(p.add_variable(Eigen::Vector2d::Zero(), euclidean_manifold(2)));
	p.add_factor(d.prior, {xs[0]});
	for (const auto& [ij, f] : d.odometry)
		if (ij.second <= j) p.add_factor(f, {xs[ij.first], xs[ij.second]});
	for (const auto& [ji, f] : d.readings)
		if (ji.first <= j)
		{
			if (!ls.count(ji.second)) ls[ji.second] = p.add_variable(Eigen::Vector2d::Zero(), euclidean_manifold(2));
			p.add_factor(f, {xs[ji.first], ls[ji.second]});
		}
	std::vector<VariableId> order = xs;
	Batch b;
	for (const auto& [i, v] : ls)
	{
		order.push_back(v);
		b.landmark_order.push_back(i);
	}
	const DenseLinearSystem sys = linearize_dense(p, order);
	const Eigen::VectorXd x = sys.H.ldlt().solve(sys.b);  // from zero: one Gauss-Newton step is exact
	for (int s = 0; s <= j; s++) b.state[s] = x.segment<2>(2 * s);
	for (std::size_t k = 0; k < b.landmark_order.size(); k++)
		b.landmark[b.landmark_order[k]] = x.segment<2>(2 * (j + 1 + static_cast<int>(k)));
	b.cov = sys.H.inverse();
	return b;
}
/** Adds state j with its odometry and readings to `sm` (x: the states, l: the landmarks by id, both
 * growing); returns the landmarks it reads. */
std::vector<int> add_step(FixedLagSmoother& sm, const Data& d, int j, std::vector<VariableId>& x,
						  std::map<int, VariableId>& l, std::set<VariableId>& landmark_vars)
{
	const Eigen::Vector2d guess =
		j > 0 ? Eigen::Vector2d(sm.problem().value(x.back())[0] + 0.8, sm.problem().value(x.back())[1])
			  : Eigen::Vector2d::Zero();
	x.push_back(sm.problem().add_variable(guess, euclidean_manifold(2)));
	sm.add_state(j, x.back());
	if (j == 0) sm.add_factor(d.prior, {x[0]});
	for (const auto& [ij, f] : d.odometry)
		if (ij.second == j) sm.add_factor(f, {x[ij.first], x[j]});
	std::vector<int> read;
	for (const auto& [ji, f] : d.readings)
		if (ji.first == j)
		{
			if (!l.count(ji.second))
			{
				l[ji.second] = sm.problem().add_variable(Eigen::Vector2d(0.8 * j, 0.0), euclidean_manifold(2));
				landmark_vars.insert(l[ji.second]);
			}
			read.push_back(ji.second);
			sm.add_factor(f, {x[j], l[ji.second]});
		}
	return read;
}

/** A smoother of `window` states (`relinearized` re-linearised; 0 = all) whose updates converge to
 * rounding, so that its estimates and covariances compare with the batch's. The cost cannot resolve the
 * last digits of the estimate (a trial step there changes it by rounding alone), so the gradient and
 * step tolerances decide, not the cost's change. */
FixedLagSmootherOptions store_test_options(int window, int relinearized = 0)
{
	FixedLagSmootherOptions opt;
	opt.window = window;
	opt.relinearized = relinearized;
	opt.solver.max_iterations = 50;
	opt.solver.function_tolerance = 0;
	opt.solver.gradient_tolerance = opt.solver.parameter_tolerance = 1e-15;
	return opt;
}
}  // namespace

TEST(PriorOnlyStore, KeepsTheExactSolutionWhileLandmarksLeaveAndReturn)
{
	const Data d = make_data();
	const FixedLagSmootherOptions opt = store_test_options(kLag);
	FixedLagSmoother sm(opt);
	std::vector<VariableId> x;
	std::map<int, VariableId> l;
	std::set<VariableId> landmark_vars;
	test::RecordingClient client;
	client.handling = [&](VariableId v) { return landmark_vars.count(v) > 0 ? PriorOnly::Store : PriorOnly::Keep; };
	double worst = 0;
	int max_stored = 0, returns = 0;
	std::set<int> stored_before;
	for (int j = 0; j < kStates; j++)
	{
		for (int i : add_step(sm, d, j, x, l, landmark_vars))
			if (stored_before.count(i)) returns++;
		const UpdateSummary u = sm.update(client);
		ASSERT_TRUE(u.solver.is_solution_usable()) << "step " << j;
		max_stored = std::max(max_stored, u.prior_only_eliminated);
		stored_before.clear();
		for (const auto& [i, v] : l)
			if (sm.in_prior(v) && sm.prior().index_of(v) < 0) stored_before.insert(i);

		const Batch b = solve_batch(d, j);
		for (const auto& s : sm.states())
		{
			const int k = static_cast<int>(std::find(x.begin(), x.end(), s.var) - x.begin());
			const Eigen::Vector2d xk = Eigen::Map<const Eigen::Vector2d>(sm.problem().value(s.var));
			worst = std::max(worst, (xk - b.state.at(k)).norm());
		}
		for (const auto& [i, v] : l)
		{
			const Eigen::Vector2d li = Eigen::Map<const Eigen::Vector2d>(sm.problem().value(v));
			worst = std::max(worst, (li - b.landmark.at(i)).norm());
		}
	}
	std::printf("[store] max |estimate − batch| %.2g over %d steps; up to %d landmarks stored, %d readings of "
				"stored landmarks\n", worst, kStates, max_stored, returns);
	EXPECT_LT(worst, 1e-9);
	// The store was used, and landmarks came back out of it (0, 2 and 6 return after leaving).
	EXPECT_GE(max_stored, 2);
	EXPECT_GE(returns, 3);

	// The covariance over the window and every landmark (naming the stored ones brings them back).
	const Batch b = solve_batch(d, kStates - 1);
	std::vector<VariableId> order;
	std::vector<int> rows;
	for (const auto& s : sm.states())
	{
		order.push_back(s.var);
		const int k = static_cast<int>(std::find(x.begin(), x.end(), s.var) - x.begin());
		rows.push_back(2 * k);
	}
	for (std::size_t k = 0; k < b.landmark_order.size(); k++)
	{
		order.push_back(l.at(b.landmark_order[k]));
		rows.push_back(2 * kStates + 2 * static_cast<int>(k));
	}
	ASSERT_EQ(b.landmark_order.size(), static_cast<std::size_t>(kLandmarks));
	CovarianceRequest request;
	request.groups = {order};
	const CovarianceResult result = sm.covariances(request);
	ASSERT_TRUE(result.ok) << result.message;
	const Eigen::MatrixXd& cov = result.blocks[0];
	EXPECT_LT((cov - linearize_dense(sm.problem(), order).H.inverse()).norm(), 1e-9 * cov.norm());
	Eigen::MatrixXd want(cov.rows(), cov.cols());
	for (std::size_t r = 0; r < rows.size(); r++)
		for (std::size_t c = 0; c < rows.size(); c++)
			want.block<2, 2>(2 * static_cast<Eigen::Index>(r), 2 * static_cast<Eigen::Index>(c)) =
				b.cov.block<2, 2>(rows[r], rows[c]);
	EXPECT_LT((cov - want).norm(), 1e-9 * want.norm());
}

// The covariance of the linear tail's states (2 re-linearised states and a tail of 5: W = 7 > K = 2):
// at every step, update()'s covariance of each tail state — the oldest is the one leaving at lag W —
// and of the oldest jointly with the newest state must be the batch's marginal, the dense inverse of
// the information of every factor so far (the problem is linear: the window's model is the batch's).
// The tail's separators hold landmarks that only the prior touches by then, kept in the solve, stored
// or eliminated from it: their conditionals are substituted too. After the run, covariances() of every
// tail state and landmark jointly. Also the tail's means against the batch's.
class LaggedCovariance : public ::testing::TestWithParam<PriorOnly>
{
};

namespace
{
/** The batch's joint covariance of `group` (states x, landmarks l by id). */
Eigen::MatrixXd batch_covariance(const Batch& b, const std::vector<VariableId>& group, const std::vector<VariableId>& x,
								 const std::map<int, VariableId>& l)
{
	std::vector<int> rows;  // in b.cov: states 0..j, then the landmarks seen
	for (VariableId v : group)
	{
		const auto s = std::find(x.begin(), x.end(), v);
		if (s != x.end()) rows.push_back(2 * static_cast<int>(s - x.begin()));
		for (std::size_t k = 0; k < b.landmark_order.size(); k++)
			if (l.at(b.landmark_order[k]) == v) rows.push_back(2 * static_cast<int>(b.state.size() + k));
	}
	Eigen::MatrixXd out(2 * rows.size(), 2 * rows.size());
	for (std::size_t r = 0; r < rows.size(); r++)
		for (std::size_t c = 0; c < rows.size(); c++)
			out.block<2, 2>(2 * static_cast<Eigen::Index>(r), 2 * static_cast<Eigen::Index>(c)) =
				b.cov.block<2, 2>(rows[r], rows[c]);
	return out;
}
}  // namespace

TEST_P(LaggedCovariance, OfTheLinearTailIsTheBatchMarginal)
{
	const Data d = make_data();
	const FixedLagSmootherOptions opt = store_test_options(7, 2);
	FixedLagSmoother sm(opt);
	std::vector<VariableId> x;
	std::map<int, VariableId> l;
	std::set<VariableId> landmark_vars;
	test::RecordingClient client;
	client.handling = [&](VariableId v) { return landmark_vars.count(v) > 0 ? GetParam() : PriorOnly::Keep; };
	double worst = 0, mean_err = 0;
	int tail_groups = 0;
	CovarianceRequest request;
	for (int j = 0; j < kStates; j++)
	{
		add_step(sm, d, j, x, l, landmark_vars);
		request.groups.clear();
		for (const LinearState& s : sm.linear_states()) request.groups.push_back({s.var});
		if (!request.groups.empty()) request.groups.push_back({request.groups.front()[0], x[j]});
		tail_groups += static_cast<int>(request.groups.size());
		const UpdateSummary u = sm.update(client, request);
		ASSERT_TRUE(u.covariance.ok) << u.covariance.message;
		const Batch b = solve_batch(d, j);
		for (const LinearState& s : sm.linear_states())
			mean_err = std::max(mean_err, (Eigen::Map<const Eigen::Vector2d>(s.value.data()) -
										   b.state.at(static_cast<int>(s.time)))
											  .norm());
		for (std::size_t g = 0; g < request.groups.size(); g++)
		{
			const Eigen::MatrixXd want = batch_covariance(b, request.groups[g], x, l);
			worst = std::max(worst, (u.covariance.blocks[g] - want).norm() / want.norm());
		}
	}
	request.groups = {{}};
	for (const LinearState& s : sm.linear_states()) request.groups[0].push_back(s.var);
	for (const auto& [i, v] : l) request.groups[0].push_back(v);
	const CovarianceResult r = sm.covariances(request);
	ASSERT_TRUE(r.ok) << r.message;
	const Eigen::MatrixXd want = batch_covariance(solve_batch(d, kStates - 1), request.groups[0], x, l);
	const double end = (r.blocks[0] - want).norm() / want.norm();
	std::printf("[lagged covariance] worst relative error %.2g over %d tail groups, %.2g at the end; tail means %.2g "
				"from the batch's\n", worst, tail_groups, end, mean_err);
	EXPECT_GT(tail_groups, 60);
	// Stored landmarks are the exception: when a state leaves while they are stored, the store keeps
	// their conditional given the others (the state integrated out) and the tail the state's given its
	// separator, without the coupling of the two; a landmark that returns no longer informs the tail
	// states through it. The window's model is then not the batch's, for the tail's means as well.
	const bool exact = GetParam() != PriorOnly::Store;
	EXPECT_LT(worst, exact ? 1e-9 : 2e-2);
	EXPECT_LT(end, exact ? 1e-9 : 2e-2);
	EXPECT_LT(mean_err, exact ? 1e-9 : 1e-3);
}

INSTANTIATE_TEST_SUITE_P(FixedLagSmoother, LaggedCovariance,
						 ::testing::Values(PriorOnly::Keep, PriorOnly::Store, PriorOnly::Eliminate),
						 [](const ::testing::TestParamInfo<PriorOnly>& i) {
							 return std::string(i.param == PriorOnly::Keep    ? "Keep"
												: i.param == PriorOnly::Store ? "Store"
																			  : "Eliminate");
						 });
