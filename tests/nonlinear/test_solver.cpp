// Solver tests on a small SE(3) + point problem with a test-local factor (pose ⊖ point observation).
#include <gtest/gtest.h>

#include "random_draws.h"
#include <swba/core/numeric_diff.h>
#include "support/dense_linearization.h"
#include <swba/nonlinear/solver.h>

#include <Eigen/Dense>
#include <random>

using namespace swba;

namespace
{
/** r = T⁻¹·p − z: a point p (world) seen in the frame of pose T. */
class PointInFrameFactor final : public Factor
{
   public:
	explicit PointInFrameFactor(const Eigen::Vector3d& z) : Factor(3, {6, 3}), z_(z) {}
	bool evaluate(const double* const* x, double* residual, double* const* jac) const override
	{
		const auto T = se3_view(x[0]);
		const Eigen::Matrix3d R = T.leftCols<3>();
		const Eigen::Vector3d l = R.transpose() * (Eigen::Map<const Eigen::Vector3d>(x[1]) - T.col(3));
		Eigen::Map<Eigen::Vector3d>{residual} = l - z_;
		if (jac && jac[0])
		{
			Eigen::Map<Eigen::Matrix<double, 3, 6, Eigen::RowMajor>> J(jac[0]);
			J.leftCols<3>() = -Eigen::Matrix3d::Identity();
			J.rightCols<3>() = skew(l);
		}
		if (jac && jac[1]) Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>{jac[1]} = R.transpose();
		return true;
	}

   private:
	Eigen::Vector3d z_;
};

/** r = x_j − x_i − d on R³ (a linear "odometry" between points). */
class PointDifferenceFactor final : public Factor
{
   public:
	explicit PointDifferenceFactor(const Eigen::Vector3d& d) : Factor(3, {3, 3}), d_(d) {}
	bool evaluate(const double* const* x, double* r, double* const* jac) const override
	{
		for (int i = 0; i < 3; i++) r[i] = x[1][i] - x[0][i] - d_[i];
		if (jac && jac[0]) Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>{jac[0]} = -Eigen::Matrix3d::Identity();
		if (jac && jac[1]) Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>{jac[1]} = Eigen::Matrix3d::Identity();
		return true;
	}

   private:
	Eigen::Vector3d d_;
};

struct Scene
{
	Problem problem;
	std::vector<VariableId> poses, points;
	std::vector<mrpt::poses::CPose3D> true_poses;
	std::vector<Eigen::Vector3d> true_points;
};

/** 5 poses, 30 points, every point seen by every pose; noisy measurements; perturbed start. */
Scene make_scene(double meas_noise, double init_noise, unsigned seed = 42, int num_points = 30)
{
	std::mt19937 rng(seed);
	std::normal_distribution<double> N(0, 1);
	Scene s;
	for (int i = 0; i < 5; i++)
		s.true_poses.emplace_back(0.5 * i, 0.1 * i, 0.05 * i, 0.1 * i, -0.05 * i, 0.02 * i);
	for (int j = 0; j < num_points; j++) s.true_points.push_back(Eigen::Vector3d(3, 0, 0) + normal3(N, rng));
	for (const auto& P : s.true_poses)
	{
		const Eigen::Vector3d da = init_noise * normal3(N, rng);  // (roll, pitch, yaw drawn first)
		const Eigen::Vector3d dt = init_noise * normal3(N, rng);
		const mrpt::poses::CPose3D noisy = P + mrpt::poses::CPose3D(dt.x(), dt.y(), dt.z(), da.x(), da.y(), da.z());
		s.poses.push_back(s.problem.add_pose(noisy));
	}
	for (const auto& p : s.true_points)
	{
		const Eigen::Vector3d noisy = p + init_noise * normal3(N, rng);
		s.points.push_back(s.problem.add_variable(noisy, euclidean_manifold(3), Group::Eliminable));
	}
	for (size_t i = 0; i < s.poses.size(); i++)
		for (size_t j = 0; j < s.points.size(); j++)
		{
			double l[3];
			s.true_poses[i].inverseComposePoint(s.true_points[j].x(), s.true_points[j].y(), s.true_points[j].z(),
												l[0], l[1], l[2]);
			const Eigen::Vector3d z =
				Eigen::Vector3d(l[0], l[1], l[2]) + meas_noise * normal3(N, rng);
			auto f = std::make_shared<PointInFrameFactor>(z);
			f->set_sigma(0.05);
			s.problem.add_factor(f, {s.poses[i], s.points[j]});
		}
	s.problem.set_constant(s.poses[0]);
	return s;
}

// The scene's problem after one LM step computed densely from the full normal equations of every
// non-constant variable: δ = (H + λ·clamp(diag H))⁻¹ (−g), λ = 1/initial_trust_region_radius.
Problem after_dense_lm_step(const Scene& scene, const SolverOptions& opt)
{
	std::vector<VariableId> order;
	for (size_t i = 1; i < scene.poses.size(); i++) order.push_back(scene.poses[i]);
	for (auto p : scene.points) order.push_back(p);
	const auto sys = linearize_dense(scene.problem, order);
	Eigen::MatrixXd A = sys.H;
	for (int i = 0; i < A.rows(); i++)
		A(i, i) += (1.0 / opt.initial_trust_region_radius) * std::clamp(sys.H(i, i), opt.min_lm_diagonal, opt.max_lm_diagonal);
	const Eigen::VectorXd delta = A.ldlt().solve(sys.b);
	Problem expected = scene.problem;
	for (size_t k = 0; k < order.size(); k++)
	{
		const auto& v = expected.variable(order[k]);
		std::vector<double> x(v.value.size());
		v.manifold->plus(v.value.data(), delta.data() + sys.offsets[k], x.data());
		expected.set_value(order[k], x.data());
	}
	return expected;
}

std::vector<double> all_values(const Problem& p)
{
	std::vector<double> v;
	for (const auto& [id, var] : p.variables()) v.insert(v.end(), var.value.begin(), var.value.end());
	return v;
}
}  // namespace

TEST(Solver, TestFactorJacobiansMatchNumeric)
{
	auto s = make_scene(0.01, 0.1);
	const auto& fe = s.problem.factor(s.problem.factors().begin()->first);
	const auto cmp = compare_jacobians(*fe.factor, {s.problem.value(fe.variables[0]), s.problem.value(fe.variables[1])},
									   {SE3Manifold::instance().get(), euclidean_manifold(3).get()});
	EXPECT_LT(cmp.max_relative_error(), 1e-6);
}

// One LM step with each linear solver equals the step computed densely from the full normal
// equations: δ = (H + λ·clamp(diag H))⁻¹ (−g), λ = 1/initial_trust_region_radius.
TEST(Solver, OneStepOfEveryLinearSolverEqualsDenseNormalEquationsStep)
{
	SolverOptions opt;
	opt.max_iterations = 1;
	opt.initial_trust_region_radius = 1e3;
	const Problem expected = after_dense_lm_step(make_scene(0.01, 0.05), opt);
	for (auto type : {LinearSolverType::DenseSchur, LinearSolverType::SparseSchur, LinearSolverType::DenseNormal,
					  LinearSolverType::SparseNormal})
	{
		auto s = make_scene(0.01, 0.05);
		opt.linear_solver = type;
		const auto summary = solve(s.problem, opt);
		ASSERT_EQ(summary.successful_steps, 1) << to_string(type);
		const auto got = all_values(s.problem), want = all_values(expected);
		ASSERT_EQ(got.size(), want.size());
		double worst = 0;
		for (size_t i = 0; i < got.size(); i++) worst = std::max(worst, std::abs(got[i] - want[i]));
		EXPECT_LT(worst, 1e-9) << to_string(type);
	}
}

TEST(Solver, ConvergesToTruthWithoutNoiseAndKeepsConstantsBitIdentical)
{
	auto s = make_scene(0.0, 0.05);
	const std::vector<double> fixed(s.problem.value(s.poses[0]), s.problem.value(s.poses[0]) + 12);
	SolverOptions opt;
	opt.max_iterations = 50;
	opt.function_tolerance = 1e-12;
	const auto summary = solve(s.problem, opt);
	EXPECT_TRUE(summary.is_solution_usable());
	EXPECT_GT(summary.initial_cost, 1.0);
	EXPECT_LT(summary.final_cost, 1e-12 * summary.initial_cost);
	// Zero-cost solutions are the truth moved by G = start0 · true0⁻¹ (pose 0 is held at its start).
	const mrpt::poses::CPose3D Gw = s.problem.pose(s.poses[0]) + (-s.true_poses[0]);
	for (size_t i = 0; i < s.poses.size(); i++)
	{
		const auto expect = Gw + s.true_poses[i];
		const auto got = s.problem.pose(s.poses[i]);
		EXPECT_LT((got.asVectorVal() - expect.asVectorVal()).norm(), 1e-6) << "pose " << i;
	}
	for (int i = 0; i < 12; i++) EXPECT_EQ(s.problem.value(s.poses[0])[i], fixed[i]);  // bit-identical
	// Pose 0 is the true pose perturbed; the others converge to a consistent configuration.
	EXPECT_EQ(summary.num_constant_variables, 1);
	EXPECT_EQ(summary.num_eliminated_variables, 30);
	EXPECT_EQ(summary.linear_solver_used, LinearSolverType::DenseSchur);
	EXPECT_NE(summary.full_report().find("Final cost:"), std::string::npos);
}

TEST(Solver, SchurAndNormalEquationsReachTheSameMinimum)
{
	double costs[2];
	int i = 0;
	for (auto type : {LinearSolverType::SparseSchur, LinearSolverType::DenseNormal})
	{
		auto s = make_scene(0.02, 0.1);
		SolverOptions opt;
		opt.linear_solver = type;
		opt.function_tolerance = 1e-12;
		opt.num_threads = 2;
		costs[i++] = solve(s.problem, opt).final_cost;
	}
	EXPECT_NEAR(costs[0], costs[1], 1e-9 * costs[1]);
}

TEST(Solver, DeterministicAcrossThreadCounts)
{
	std::vector<double> results[2];
	for (int t = 1; t <= 2; t++)
	{
		auto s = make_scene(0.02, 0.1, 42, 900);  // 4500 factors: above the parallel threshold
		SolverOptions opt;
		opt.num_threads = t;
		solve(s.problem, opt);
		results[t - 1] = all_values(s.problem);
	}
	EXPECT_EQ(results[0], results[1]);
}

// A factor between two eliminable points (like a marginalisation prior over landmarks): the explicit
// Schur solvers reject it; Auto keeps the two linked points in the reduced system, eliminates the
// other 28, and its one LM step equals the dense full normal-equations step.
TEST(Solver, AutoKeepsLinkedEliminableVariablesAndStillEliminatesTheRest)
{
	auto build = [] {
		auto s = make_scene(0.01, 0.05);
		auto f = std::make_shared<PointDifferenceFactor>(Eigen::Vector3d(0.1, -0.2, 0.05));
		s.problem.add_factor(f, {s.points[0], s.points[1]});
		return s;
	};
	SolverOptions opt;
	opt.linear_solver = LinearSolverType::DenseSchur;
	auto rejected = build();
	EXPECT_THROW(solve(rejected.problem, opt), std::invalid_argument);

	opt.max_iterations = 1;
	opt.initial_trust_region_radius = 1e3;
	const Problem expected = after_dense_lm_step(build(), opt);

	auto s = build();
	opt.linear_solver = LinearSolverType::Auto;
	const auto summary = solve(s.problem, opt);
	EXPECT_EQ(summary.linear_solver_used, LinearSolverType::DenseSchur);
	EXPECT_EQ(summary.num_eliminated_variables, 28);
	EXPECT_EQ(summary.num_kept_variables, 4 + 2);
	EXPECT_EQ(summary.reduced_dim, 4 * 6 + 2 * 3);
	ASSERT_EQ(summary.successful_steps, 1);
	const auto got = all_values(s.problem), want = all_values(expected);
	ASSERT_EQ(got.size(), want.size());
	double worst = 0;
	for (size_t i = 0; i < got.size(); i++) worst = std::max(worst, std::abs(got[i] - want[i]));
	EXPECT_LT(worst, 1e-9);
}

namespace
{
/** r = e + J (x ⊟ x_lin), Jacobian J whatever x (a marginalisation prior); declares its Jacobian
 * constant or not (then the solver forms its Jᵀ J at every assembly). */
class LinearTestPrior final : public Factor
{
   public:
	LinearTestPrior(Eigen::MatrixXd J, Eigen::VectorXd e, std::vector<std::vector<double>> x_lin,
					std::vector<std::shared_ptr<const Manifold>> manifolds, bool declare_constant)
		: Factor(static_cast<int>(J.rows()), dims(manifolds)), J_(std::move(J)), e_(std::move(e)),
		  x_lin_(std::move(x_lin)), manifolds_(std::move(manifolds)), constant_(declare_constant)
	{
	}
	bool evaluate(const double* const* x, double* r, double* const* jac) const override
	{
		Eigen::VectorXd d(J_.cols());
		for (size_t i = 0, off = 0; i < manifolds_.size(); off += manifolds_[i]->tangent_size(), i++)
			manifolds_[i]->minus(x[i], x_lin_[i].data(), d.data() + off);
		Eigen::Map<Eigen::VectorXd>(r, J_.rows()) = e_ + J_ * d;
		for (size_t i = 0, off = 0; i < manifolds_.size(); off += manifolds_[i]->tangent_size(), i++)
			if (jac && jac[i])
				Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
					jac[i], J_.rows(), manifolds_[i]->tangent_size()) =
					J_.middleCols(static_cast<Eigen::Index>(off), manifolds_[i]->tangent_size());
		return true;
	}
	bool constant_jacobian() const override { return constant_; }

   private:
	static std::vector<int> dims(const std::vector<std::shared_ptr<const Manifold>>& m)
	{
		std::vector<int> d;
		for (const auto& x : m) d.push_back(x->tangent_size());
		return d;
	}
	Eigen::MatrixXd J_;
	Eigen::VectorXd e_;
	std::vector<std::vector<double>> x_lin_;
	std::vector<std::shared_ptr<const Manifold>> manifolds_;
	bool constant_;
};

/** The scene with a linear prior over pose 1 and points 0, 1 (linked: kept) and one over pose 2 and
 * point 2 (eliminated: its H_lp block comes from the prior); `formed`: priors not declared constant. */
Scene scene_with_linear_priors(bool formed)
{
	auto s = make_scene(0.01, 0.05);
	std::mt19937 rng(7);
	std::normal_distribution<double> N(0, 1);
	auto add_prior = [&](const std::vector<VariableId>& vars) {
		std::vector<std::vector<double>> x_lin;
		std::vector<std::shared_ptr<const Manifold>> manifolds;
		int n = 0;
		for (VariableId v : vars)
		{
			x_lin.push_back(s.problem.variable(v).value);
			manifolds.push_back(s.problem.variable(v).manifold);
			n += manifolds.back()->tangent_size();
		}
		const Eigen::MatrixXd J = Eigen::MatrixXd::NullaryExpr(n, n, [&] { return 10.0 * N(rng); });
		const Eigen::VectorXd e = Eigen::VectorXd::NullaryExpr(n, [&] { return N(rng); });
		s.problem.add_factor(std::make_shared<LinearTestPrior>(J, e, x_lin, manifolds, !formed), vars);
	};
	add_prior({s.poses[1], s.points[0], s.points[1]});
	add_prior({s.poses[2], s.points[2]});
	return s;
}
}  // namespace

// A factor with a constant Jacobian (the marginalisation prior) has its Jᵀ J blocks formed once per
// solve and added from there: every LM iteration sees the same normal equations as when they are
// formed from its Jacobians at each assembly, so the two solves agree to the last bit.
TEST(Solver, ConstantJacobianFactorsGiveTheSameSolveAsTheirJacobians)
{
	SolverOptions opt;
	opt.function_tolerance = 1e-14;
	auto cached = scene_with_linear_priors(false), formed = scene_with_linear_priors(true);
	const auto a = solve(cached.problem, opt), b = solve(formed.problem, opt);
	EXPECT_EQ(a.num_kept_variables, 4 + 2);
	EXPECT_GE(a.successful_steps, 3);
	EXPECT_EQ(a.iterations, b.iterations);
	EXPECT_EQ(a.final_cost, b.final_cost);
	EXPECT_EQ(all_values(cached.problem), all_values(formed.problem));
}

TEST(Solver, InvalidOptionsAreRejected)
{
	auto s = make_scene(0.0, 0.0);
	SolverOptions opt;
	opt.num_threads = 0;
	EXPECT_THROW(solve(s.problem, opt), std::invalid_argument);
	opt = SolverOptions();
	opt.initial_trust_region_radius = -1;
	EXPECT_THROW(opt.validate(), std::invalid_argument);
}

TEST(Solver, RobustLossGradientMatchesNumericGradientOfRobustCost)
{
	auto s = make_scene(0.3, 0.05);  // large noise: many residuals in the robust regime
	for (const auto& loss_name : {"huber", "cauchy"})
	{
		Problem p;
		std::vector<VariableId> order;
		for (const auto& [id, v] : s.problem.variables()) order.push_back(p.add_variable(v.value.data(), v.manifold, v.group));
		auto loss = make_loss(loss_name, 1.0);
		for (const auto& [fid, fe] : s.problem.factors())
			p.add_factor(fe.factor, {order[fe.variables[0]], order[fe.variables[1]]}, loss);
		const auto sys = linearize_dense(p, order);
		// Numeric gradient of the robust cost along each tangent coordinate of a few variables.
		for (int k : {1, 3, 7})
		{
			const auto& var = p.variable(order[k]);
			const int t = var.manifold->tangent_size();
			for (int c = 0; c < t; c++)
			{
				const double h = 1e-6;
				std::vector<double> x0 = var.value, xp(x0.size()), xm(x0.size());
				Eigen::VectorXd d = Eigen::VectorXd::Zero(t);
				d[c] = h;
				var.manifold->plus(x0.data(), d.data(), xp.data());
				d[c] = -h;
				var.manifold->plus(x0.data(), d.data(), xm.data());
				p.set_value(order[k], xp.data());
				const double cp = p.cost();
				p.set_value(order[k], xm.data());
				const double cm = p.cost();
				p.set_value(order[k], x0.data());
				const double numeric = (cp - cm) / (2 * h);
				EXPECT_NEAR(-sys.b[sys.offsets[k] + c], numeric, 1e-5 * std::max(1.0, std::abs(numeric))) << loss_name;
			}
		}
	}
}

// Robust losses through the whole LM loop (residual-only trial evaluations included): outliers are
// down-weighted and the inliers' solution is recovered.
TEST(Solver, SolvesWithRobustLossDespiteOutliers)
{
	for (const char* loss_name : {"huber", "cauchy"})
	{
		auto s = make_scene(0.0, 0.05);
		Problem p;
		std::vector<VariableId> order;
		for (const auto& [id, v] : s.problem.variables()) order.push_back(p.add_variable(v.value.data(), v.manifold, v.group));
		p.set_constant(order[0]);
		auto loss = make_loss(loss_name, 1.0);
		int k = 0;
		for (const auto& [fid, fe] : s.problem.factors())
		{
			std::shared_ptr<const Factor> f = fe.factor;
			if (k++ % 25 == 0)  // a gross outlier: the point measured 2 m away
			{
				auto bad = std::make_shared<PointInFrameFactor>(Eigen::Vector3d(2.0, -2.0, 1.0));
				bad->set_sigma(0.05);
				f = bad;
			}
			p.add_factor(f, {order[fe.variables[0]], order[fe.variables[1]]}, loss);
		}
		SolverOptions opt;
		opt.max_iterations = 100;
		const auto summary = solve(p, opt);
		EXPECT_TRUE(summary.is_solution_usable()) << loss_name;
		EXPECT_LT(summary.final_cost, summary.initial_cost) << loss_name;
		// Poses recover the truth (moved by the gauge of pose 0) to within a few millimetres.
		const mrpt::poses::CPose3D G = p.pose(order[0]) + (-s.true_poses[0]);
		for (size_t i = 1; i < s.poses.size(); i++)
			EXPECT_LT((p.pose(order[i]).asVectorVal() - (G + s.true_poses[i]).asVectorVal()).norm(), 5e-3)
				<< loss_name << " pose " << i;
	}
}
