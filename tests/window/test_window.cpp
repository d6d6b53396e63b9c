// Sliding-window estimator: equivalence with batch, marginalisation pipeline on a linear-Gaussian
// chain, FEJ keeps the prior free of information along the gauge directions.
#include <gtest/gtest.h>
#include <swba/factors/linear_prior.h>
#include <swba/linear/marginal.h>
#include <swba/nonlinear/linearization.h>

#include <Eigen/Dense>

#include "window_test_utils.h"

using namespace swba;
using namespace swba::estimators;

namespace
{
const io::Rawlog& demo_rawlog()
{
	static const io::Rawlog r = io::read_rawlog(test::dataset("kf-slam_6D_demo.rawlog"));
	return r;
}

io::Rawlog first_steps(const io::Rawlog& r, std::size_t n)
{
	io::Rawlog out = r;
	out.steps.resize(std::min(n, r.steps.size()));
	return out;
}

/** r = A·[x_i; x_j] − z over Euclidean scalars (a linear-Gaussian factor). */
class LinearFactor final : public Factor
{
   public:
	LinearFactor(Eigen::MatrixXd A, Eigen::VectorXd z, std::vector<int> dims)
		: Factor(static_cast<int>(A.rows()), dims), A_(std::move(A)), z_(std::move(z))
	{
	}
	bool evaluate(const double* const* x, double* r, double* const* jac) const override
	{
		Eigen::VectorXd xs(A_.cols());
		int off = 0;
		for (int i = 0; i < num_variables(); i++)
			for (int c = 0; c < tangent_dims()[i]; c++) xs[off++] = x[i][c];
		Eigen::Map<Eigen::VectorXd> rv(r, A_.rows());
		rv = A_ * xs - z_;
		off = 0;
		for (int i = 0; i < num_variables(); i++)
		{
			if (jac && jac[i])
				Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(jac[i], A_.rows(),
																									 tangent_dims()[i]) =
					A_.middleCols(off, tangent_dims()[i]);
			off += tangent_dims()[i];
		}
		return true;
	}

   private:
	Eigen::MatrixXd A_;
	Eigen::VectorXd z_;
};
}  // namespace

// The window pipeline (dense linearisation of the factors touching the oldest state, Schur
// complement, prior kept as (J, e, x_lin)) on a linear-Gaussian chain x0 - x1 - x2 - x3 (2-D states):
// the prior is the exact marginal, and solving the reduced problem gives the full solution.
TEST(WindowMarginalization, LinearGaussianChainPriorIsTheExactMarginal)
{
	Problem p;
	std::vector<VariableId> x;
	for (int i = 0; i < 4; i++) x.push_back(p.add_variable(Eigen::Vector2d(0.1 * i, -0.2 * i), euclidean_manifold(2)));
	auto add_between = [&](int i, int j, double dx, double dy, double sigma) {
		Eigen::MatrixXd A(2, 4);
		A << -1, 0, 1, 0, 0, -1, 0, 1;
		auto f = std::make_shared<LinearFactor>(A, Eigen::Vector2d(dx, dy), std::vector<int>{2, 2});
		f->set_sigma(sigma);
		return p.add_factor(f, {x[i], x[j]});
	};
	{
		auto f = std::make_shared<LinearFactor>(Eigen::MatrixXd::Identity(2, 2), Eigen::Vector2d(0.5, 0.1),
												std::vector<int>{2});
		f->set_sigma(0.1);
		p.add_factor(f, {x[0]});
	}
	add_between(0, 1, 1.0, 0.0, 0.2);
	add_between(1, 2, 1.0, 0.5, 0.3);
	add_between(2, 3, 0.8, -0.2, 0.25);
	add_between(0, 2, 2.1, 0.4, 0.5);  // a loop, so that x1 and x2 are both linked to x0

	// Reference: the full solution and covariance.
	const auto full = linearize_dense(p, x);
	const Eigen::VectorXd full_step = full.H.ldlt().solve(full.b);
	const Eigen::MatrixXd cov = full.H.inverse();

	// Marginalise x0 as the window does.
	std::vector<FactorId> fm(p.variable(x[0]).factors.begin(), p.variable(x[0]).factors.end());
	const std::vector<VariableId> keep{x[1], x[2]};
	const auto sys = linearize_dense(p, {x[1], x[2], x[0]}, fm);
	const auto m = marginalize(sys.H, sys.b, {0, 1, 2, 3}, {4, 5});
	// The prior's information equals the inverse of the marginal covariance of (x1, x2) in the
	// subgraph of the marginalised factors; with the remaining factors added, the whole equals the
	// full problem's marginal: check the latter.
	for (FactorId f : fm) p.remove_factor(f);
	std::vector<std::vector<double>> xlin{p.variable(x[1]).value, p.variable(x[2]).value};
	p.add_factor(std::make_shared<LinearPriorFactor>(m.J, m.e, xlin,
													 std::vector<std::shared_ptr<const Manifold>>{
														 euclidean_manifold(2), euclidean_manifold(2)}),
				 keep);
	p.remove_variable(x[0]);
	const auto reduced = linearize_dense(p, {x[1], x[2], x[3]});
	const Eigen::MatrixXd cov_reduced = reduced.H.inverse();
	EXPECT_LT((cov_reduced - cov.bottomRightCorner(6, 6)).norm(), 1e-10 * cov.norm());
	const Eigen::VectorXd reduced_step = reduced.H.ldlt().solve(reduced.b);
	EXPECT_LT((reduced_step - full_step.tail(6)).norm(), 1e-10 * full_step.norm());
}

// With W ≥ the number of steps nothing is marginalised: the window's final estimate is the batch
// solution.
TEST(SlidingWindow, WindowLargerThanRunEqualsBatch)
{
	const auto rawlog = first_steps(demo_rawlog(), 60);
	SlidingWindowOptions opt;
	opt.window_size = 100;
	opt.solver.function_tolerance = 1e-14;
	opt.solver.max_iterations = 30;
	SlidingWindowEstimator est(opt);
	for (const auto& s : rawlog.steps) est.process(s);
	est.finish();
	const auto batch = run_batch(rawlog, opt, 100);
	const auto& lag = est.lagged_trajectory();
	ASSERT_EQ(lag.size(), batch.trajectory.size());
	double worst = 0;
	for (std::size_t i = 0; i < lag.size(); i++)
	{
		EXPECT_EQ(lag.stamps[i], batch.trajectory.stamps[i]);
		worst = std::max(worst, (lag.poses[i].asVectorVal() - batch.trajectory.poses[i].asVectorVal()).norm());
	}
	EXPECT_LT(worst, 1e-6);
}

namespace
{
/** ‖H_prior·N‖ / ‖H_prior‖ after `steps` steps of a free-gauge window. */
double gauge_leak(bool fej, LandmarkParameterization lp, std::size_t steps)
{
	const auto rawlog = first_steps(demo_rawlog(), steps);
	SlidingWindowOptions opt;
	opt.window_size = 8;
	opt.gauge = GaugeMode::Free;
	opt.first_estimate_jacobians = fej;
	opt.landmarks = lp;
	// A noisier sensor model than the data so that estimates move between linearisations.
	SlidingWindowEstimator est(opt);
	for (const auto& s : rawlog.steps) est.process(s);
	const Eigen::MatrixXd H = est.prior_information();
	const Eigen::MatrixXd N = est.prior_gauge_directions();
	EXPECT_EQ(N.rows(), H.rows());
	EXPECT_GT(H.rows(), 0);
	return (H * N).norm() / H.norm();
}
}  // namespace

TEST(SlidingWindow, FejPriorHasNoInformationAlongGaugeDirections)
{
	for (auto lp : {LandmarkParameterization::InverseDepth, LandmarkParameterization::Xyz})
	{
		const double with_fej = gauge_leak(true, lp, 20);
		const double without_fej = gauge_leak(false, lp, 20);
		EXPECT_LE(with_fej, 1e-8) << to_string(lp);
		// Without FEJ the prior does gain spurious information: shows that the check can fail.
		EXPECT_GT(without_fej, 100 * with_fej) << to_string(lp);
		std::cout << "[gauge leak] " << to_string(lp) << ": FEJ " << with_fej << ", no FEJ " << without_fej << "\n";
	}
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
