// A small estimator of another kind than range-bearing SLAM, built on the fixed-lag smoother through
// its public header only: a 1-D constant-velocity chain whose state is one Euclidean variable
// [position, velocity] per time step, with process factors between consecutive states and position
// measurements. The model is linear-Gaussian, so marginalisation (and the linear tail's conditionals)
// are exact: after the run, the estimates of the states the smoother still holds must equal the batch
// solution of all the data.
#include <gtest/gtest.h>
#include <swba/core/factor.h>
#include <swba/core/manifold.h>
#include <swba/smoother/fixed_lag_smoother.h>

#include <Eigen/Core>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

using namespace swba;
using namespace swba::smoother;

namespace
{
constexpr double kDt = 0.5;

/** Constant velocity over kDt: r = x_j − F x_i with F = [1 dt; 0 1], white acceleration noise. */
class ProcessFactor final : public Factor
{
   public:
	ProcessFactor() : Factor(2, {2, 2})
	{
		const double q = 0.3;  // acceleration spectral density
		Eigen::Matrix2d Q;
		Q << q * kDt * kDt * kDt / 3, q * kDt * kDt / 2, q * kDt * kDt / 2, q * kDt;
		set_information(Q.inverse());
	}
	bool evaluate(const double* const* x, double* r, double* const* jac) const override
	{
		const Eigen::Map<const Eigen::Vector2d> xi(x[0]), xj(x[1]);
		Eigen::Matrix2d F;
		F << 1, kDt, 0, 1;
		Eigen::Map<Eigen::Vector2d> res(r);
		res = xj - F * xi;
		using RowMajor2d = Eigen::Matrix<double, 2, 2, Eigen::RowMajor>;
		if (jac && jac[0])
		{
			Eigen::Map<RowMajor2d> Ji(jac[0]);
			Ji = -F;
		}
		if (jac && jac[1])
		{
			Eigen::Map<RowMajor2d> Jj(jac[1]);
			Jj.setIdentity();
		}
		return true;
	}
};

/** A position measurement: r = p − z. */
class PositionFactor final : public Factor
{
   public:
	PositionFactor(double z, double sigma) : Factor(1, {2}), z_(z) { set_sigma(sigma); }
	bool evaluate(const double* const* x, double* r, double* const* jac) const override
	{
		r[0] = x[0][0] - z_;
		if (jac && jac[0])
		{
			jac[0][0] = 1;
			jac[0][1] = 0;
		}
		return true;
	}

   private:
	double z_;
};

/** A prior on the first state: r = x − x0. */
class StatePrior final : public Factor
{
   public:
	StatePrior() : Factor(2, {2}) { set_sigma(1.0); }
	bool evaluate(const double* const* x, double* r, double* const* jac) const override
	{
		r[0] = x[0][0];
		r[1] = x[0][1] - 1.0;
		if (jac && jac[0])
		{
			Eigen::Map<Eigen::Matrix<double, 2, 2, Eigen::RowMajor>> J(jac[0]);
			J.setIdentity();
		}
		return true;
	}
};

/** Position readings of a target accelerating gently, with deterministic "noise". */
double reading(int k) { return 1.0 * k * kDt + 0.02 * k * k * kDt * kDt + 0.3 * std::sin(1.7 * k); }

SolverOptions tight()
{
	SolverOptions s;
	s.max_iterations = 50;
	s.function_tolerance = s.gradient_tolerance = s.parameter_tolerance = 1e-14;
	return s;
}

/** The estimator: one state per step; readings at every other step (the velocity is only observed
 * through the process model). As the smoother's client it keeps the final estimates of the states
 * that leave. */
struct ChainEstimator : SmootherClient
{
	FixedLagSmoother sm;
	std::vector<VariableId> x;
	std::vector<LinearState> lagged;

	explicit ChainEstimator(const FixedLagSmootherOptions& o) : sm(o) {}

	void left(const TimedState& s, const std::vector<double>& value) override { lagged.push_back({s.time, s.var, value}); }

	void add_step(int k)
	{
		const Eigen::Vector2d guess(k * kDt, 1.0);
		x.push_back(sm.problem().add_variable(guess, euclidean_manifold(2)));
		sm.add_state(k * kDt, x.back());
		if (k == 0)
			sm.add_factor(std::make_shared<StatePrior>(), {x[0]});
		else
			sm.add_factor(std::make_shared<ProcessFactor>(), {x[k - 1], x[k]});
		if (k % 2 == 0) sm.add_factor(std::make_shared<PositionFactor>(reading(k), 0.2), {x[k]});
	}
};

constexpr int kChainSteps = 40;

/** The batch solution of all kChainSteps steps: [p, v] per step. */
std::vector<Eigen::Vector2d> batch_solution()
{
	FixedLagSmootherOptions o;
	o.first_estimate_jacobians = false;
	ChainEstimator batch(o);
	for (int k = 0; k < kChainSteps; k++) batch.add_step(k);
	solve(batch.sm.problem(), tight());
	std::vector<Eigen::Vector2d> out;
	for (VariableId v : batch.x) out.emplace_back(Eigen::Map<const Eigen::Vector2d>(batch.sm.problem().value(v)));
	return out;
}

class ConstantVelocityChain : public ::testing::TestWithParam<int>
{
};
}  // namespace

// A window of 4 + GetParam() states of which 4 are re-linearised (a linear tail of GetParam()): the states
// still held after the run equal the batch solution of all the data to rounding.
TEST_P(ConstantVelocityChain, WindowEstimatesEqualTheBatchSolutionAfterMarginalising)
{
	FixedLagSmootherOptions o;
	o.window = 4 + GetParam();
	o.relinearized = 4;
	o.solver = tight();
	ChainEstimator est(o);
	for (int k = 0; k < kChainSteps; k++)
	{
		est.add_step(k);
		est.sm.update(est);
	}
	ASSERT_EQ(est.lagged.size(), static_cast<std::size_t>(kChainSteps - 4 - GetParam()));
	EXPECT_EQ(est.lagged.back().time, (kChainSteps - 5 - GetParam()) * kDt);
	EXPECT_GT(est.sm.prior().rank(), 0);
	const std::vector<Eigen::Vector2d> batch = batch_solution();
	const auto index_of = [&](VariableId v) {
		return static_cast<std::size_t>(std::find(est.x.begin(), est.x.end(), v) - est.x.begin());
	};
	std::size_t checked = 0;
	for (const LinearState& s : est.sm.linear_states())
	{
		const Eigen::Vector2d got(s.value[0], s.value[1]);
		EXPECT_LT((got - batch[index_of(s.var)]).norm(), 1e-9) << "tail state at t = " << s.time;
		checked++;
	}
	for (const TimedState& s : est.sm.states())
	{
		const Eigen::Vector2d got = Eigen::Map<const Eigen::Vector2d>(est.sm.problem().value(s.var));
		EXPECT_LT((got - batch[index_of(s.var)]).norm(), 1e-9) << "window state at t = " << s.time;
		checked++;
	}
	EXPECT_EQ(checked, static_cast<std::size_t>(4 + GetParam()));
}

INSTANTIATE_TEST_SUITE_P(Tail, ConstantVelocityChain, ::testing::Values(0, 3));

namespace
{
/** The chain, keeping its oldest re-linearised state whenever the client says so: here every state of
 * an odd step while it is among the newest `keep_span` (a stand-in for readings whose weight is still in
 * question). */
struct KeepingChain : ChainEstimator
{
	using ChainEstimator::ChainEstimator;
	int newest = -1, keep_span = 6, kept = 0;
	bool keep_relinearized(const TimedState& oldest) override
	{
		const int k = static_cast<int>(std::lround(oldest.time / kDt));
		const bool keep = k % 2 == 1 && newest - k < keep_span;
		kept += keep;
		return keep;
	}
};
}  // namespace

// States the client keeps re-linearised stay beyond options().relinearized, the tail gives way, no more
// than `window` states are ever held, every state leaves at lag W in order, and (the model being
// linear-Gaussian) the held states still equal the batch solution.
TEST(ConstantVelocityChainKeeping, KeptStatesStayWithinTheWindowAndLeaveAtLagW)
{
	FixedLagSmootherOptions o;
	o.window = 8;
	o.relinearized = 2;
	o.solver = tight();
	KeepingChain est(o);
	std::size_t most_relinearized = 0;
	for (int k = 0; k < kChainSteps; k++)
	{
		est.add_step(k);
		est.newest = k;
		est.sm.update(est);
		most_relinearized = std::max(most_relinearized, est.sm.states().size());
		EXPECT_LE(est.sm.states().size() + est.sm.linear_states().size(), 8u) << "step " << k;
	}
	EXPECT_GT(est.kept, 0);
	EXPECT_GT(most_relinearized, 3u);  // kept beyond the two re-linearised states and the new one
	ASSERT_EQ(est.lagged.size(), static_cast<std::size_t>(kChainSteps - 8));
	for (std::size_t i = 0; i < est.lagged.size(); i++) EXPECT_DOUBLE_EQ(est.lagged[i].time, i * kDt);
	const std::vector<Eigen::Vector2d> batch = batch_solution();
	for (const TimedState& s : est.sm.states())
	{
		const auto i = static_cast<std::size_t>(std::find(est.x.begin(), est.x.end(), s.var) - est.x.begin());
		EXPECT_LT((Eigen::Map<const Eigen::Vector2d>(est.sm.problem().value(s.var)) - batch[i]).norm(), 1e-9);
	}
}
