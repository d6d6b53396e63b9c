// swba::solve on BAL: one LM step equals a dense LM step on the full (not Schur-reduced) normal
// equations built here from the factors' Jacobians; short solves agree across linear solvers and
// thread counts; a problem with no evaluable factor fails.
#include <gtest/gtest.h>

#include "bal_test_data.h"
#include <swba/apps/bal.h>
#include <swba/factors/snavely_reprojection.h>
#include <swba/io/bal.h>
#include <swba/problems/bal.h>
#include <swba/nonlinear/solver.h>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace
{

/** Full normal equations H = JᵀJ, g = Jᵀr over [cameras (9 each); points (3 each)], built densely
 * from the Snavely factors' analytic Jacobians. */
struct DenseNormalEquations
{
	Eigen::MatrixXd H;
	Eigen::VectorXd g;
	double cost = 0;
};

DenseNormalEquations build_dense(const swba::io::BalProblem& bal)
{
	const int nc = bal.num_cameras, np = bal.num_points;
	const int n = 9 * nc + 3 * np;
	DenseNormalEquations ne;
	ne.H.setZero(n, n);
	ne.g.setZero(n);
	for (const auto& o : bal.observations)
	{
		const swba::SnavelyReprojectionFactor f(o.x, o.y);
		const double* x[2] = {bal.camera(o.camera), bal.point(o.point)};
		Eigen::Matrix<double, 2, 9, Eigen::RowMajor> Jc;
		Eigen::Matrix<double, 2, 3, Eigen::RowMajor> Jp;
		Eigen::Vector2d r;
		double* jac[2] = {Jc.data(), Jp.data()};
		EXPECT_TRUE(f.evaluate(x, r.data(), jac));
		Eigen::Matrix<double, 2, 12> J;
		J << Jc, Jp;
		const int ci = 9 * o.camera, pi = 9 * nc + 3 * o.point;
		const Eigen::Matrix<double, 12, 12> JtJ = J.transpose() * J;
		const Eigen::Matrix<double, 12, 1> Jtr = J.transpose() * r;
		ne.H.block<9, 9>(ci, ci) += JtJ.topLeftCorner<9, 9>();
		ne.H.block<9, 3>(ci, pi) += JtJ.topRightCorner<9, 3>();
		ne.H.block<3, 9>(pi, ci) += JtJ.bottomLeftCorner<3, 9>();
		ne.H.block<3, 3>(pi, pi) += JtJ.bottomRightCorner<3, 3>();
		ne.g.segment<9>(ci) += Jtr.head<9>();
		ne.g.segment<3>(pi) += Jtr.tail<3>();
		ne.cost += 0.5 * r.squaredNorm();
	}
	return ne;
}

/** Concatenated parameters [cameras; points] of `bal`. */
Eigen::VectorXd stacked(const swba::io::BalProblem& bal)
{
	Eigen::VectorXd x(bal.cameras.size() + bal.points.size());
	std::copy(bal.cameras.begin(), bal.cameras.end(), x.data());
	std::copy(bal.points.begin(), bal.points.end(), x.data() + bal.cameras.size());
	return x;
}

/** `bal` restricted to its first `points` points and their observations, every camera kept: the same
 * structure as the whole problem with a smaller dense reference (its Cholesky is O(n³) in 9·cameras +
 * 3·points). */
swba::io::BalProblem first_points(const swba::io::BalProblem& bal, int points)
{
	swba::io::BalProblem out = bal;
	out.num_points = points;
	out.points.resize(static_cast<std::size_t>(swba::io::BalProblem::kPointParams * points));
	out.observations.clear();
	for (const auto& o : bal.observations)
		if (o.point < points) out.observations.push_back(o);
	return out;
}

swba::Summary solve_bal(swba::io::BalProblem& bal, swba::SolverOptions o)
{
	swba::Problem problem;
	const auto vars = swba::problems::add_bal_to_problem(bal, problem);
	const auto summary = swba::solve(problem, o);
	swba::problems::copy_values_to_bal(problem, vars, bal);
	return summary;
}
}  // namespace

TEST(BalSolve, OneLmStepEqualsDenseStepOnFullNormalEquations)
{
	const auto shipped = swba::io::read_bal(kShrink);
	ASSERT_EQ(shipped.num_cameras, 49);
	ASSERT_EQ(shipped.num_points, 1800);
	const auto bal0 = first_points(shipped, 900);
	std::vector<int> seen(49, 0);
	for (const auto& o : bal0.observations) seen[static_cast<std::size_t>(o.camera)]++;
	// Every camera keeps more residual rows than its 9 parameters (at least 6 observations of the 900 points).
	ASSERT_GE(*std::min_element(seen.begin(), seen.end()), 5);

	// Reference: δ = −(H + λ·clamp(diag H, 1e-6, 1e32))⁻¹ g with λ = 1/μ₀, μ₀ = 1e4 (the solver's
	// documented LM damping, as Ceres's LEVENBERG_MARQUARDT strategy).
	const DenseNormalEquations ne = build_dense(bal0);
	const swba::SolverOptions defaults;
	const double lambda = 1.0 / defaults.initial_trust_region_radius;
	Eigen::MatrixXd A = ne.H;
	for (int i = 0; i < A.rows(); i++)
		A(i, i) += lambda * std::clamp(ne.H(i, i), defaults.min_lm_diagonal, defaults.max_lm_diagonal);
	const Eigen::LLT<Eigen::MatrixXd> llt(A);
	ASSERT_EQ(llt.info(), Eigen::Success);
	const Eigen::VectorXd delta_ref = -llt.solve(ne.g);
	const Eigen::VectorXd x0 = stacked(bal0);

	for (auto type : {swba::LinearSolverType::DenseSchur, swba::LinearSolverType::SparseSchur})
	{
		auto bal = bal0;
		swba::SolverOptions o;
		o.max_iterations = 1;
		o.linear_solver = type;
		o.num_threads = 2;
		const auto summary = solve_bal(bal, o);
		SCOPED_TRACE(swba::to_string(type));
		EXPECT_NEAR(summary.initial_cost, ne.cost, 1e-9 * ne.cost);
		ASSERT_EQ(summary.iterations, 1);
		ASSERT_EQ(summary.successful_steps, 1) << "the first step must be accepted for the comparison";
		const Eigen::VectorXd delta = stacked(bal) - x0;
		const double rel = (delta - delta_ref).norm() / delta_ref.norm();
		EXPECT_LT(rel, 1e-9) << "|δ_ours − δ_dense| / |δ_dense| (measured 2e-12 on the first 900 points)";
		std::cout << "  " << swba::to_string(type) << ": |δ| = " << delta_ref.norm() << ", relative difference "
				  << rel << "\n";
		// The step is not tiny: it changes the cost substantially.
		EXPECT_LT(summary.final_cost, 0.9 * summary.initial_cost);
		// The accepted step's cost is the cost at x0 + δ_dense.
		auto bal_ref = bal0;
		std::copy(x0.data(), x0.data() + bal_ref.cameras.size(), bal_ref.cameras.data());
		for (size_t i = 0; i < bal_ref.cameras.size(); i++) bal_ref.cameras[i] += delta_ref[static_cast<Eigen::Index>(i)];
		for (size_t i = 0; i < bal_ref.points.size(); i++)
			bal_ref.points[i] += delta_ref[static_cast<Eigen::Index>(bal_ref.cameras.size() + i)];
		EXPECT_NEAR(summary.final_cost, build_dense(bal_ref).cost, 1e-7 * summary.final_cost);
	}
}

TEST(BalSolve, ShortSolveAgreesAcrossLinearSolversAndThreads)
{
	const auto bal0 = swba::io::read_bal(kShrink);
	swba::SolverOptions o;
	o.max_iterations = 8;
	o.function_tolerance = 0;  // run all 8 iterations
	double dense_cost = 0;
	std::vector<double> costs;
	for (auto type : {swba::LinearSolverType::DenseSchur, swba::LinearSolverType::SparseSchur})
		for (int threads : {1, 2})
		{
			auto bal = bal0;
			o.linear_solver = type;
			o.num_threads = threads;
			const auto s = solve_bal(bal, o);
			EXPECT_TRUE(s.is_solution_usable()) << s.message;
			EXPECT_EQ(s.iterations, 8);
			// Cost never increases over accepted steps.
			for (size_t k = 1; k < s.iterations_log.size(); k++)
				EXPECT_LE(s.iterations_log[k].cost, s.iterations_log[k - 1].cost);
			EXPECT_LT(s.final_cost, 0.05 * s.initial_cost);
			if (type == swba::LinearSolverType::DenseSchur && threads == 1) dense_cost = s.final_cost;
			costs.push_back(s.final_cost);
		}
	// Same thread count or not, same linear algebra up to round-off: final costs agree closely.
	for (double c : costs) EXPECT_NEAR(c, dense_cost, 1e-9 * dense_cost);
	// Evaluation and assembly are deterministic across thread counts.
	EXPECT_EQ(costs[0], costs[1]);
	EXPECT_EQ(costs[2], costs[3]);
}

// Every observation's point on its camera's plane (P.z = 0 in the camera frame): no factor can be
// evaluated at the initial values. Nothing is fitted, so the solve fails (no CONVERGENCE at cost 0), and
// `swba bal` says so after its report and writes no solution.
TEST(BalSolve, EveryFactorDroppedAtTheInitialValuesIsAFailure)
{
	const std::string text = "1 1 1\n0 0 1 1\n0 0 0 0 0 -5 500 0 0\n0 0 5\n";
	swba::io::BalProblem bal = swba::io::parse_bal(text, "allpz0.txt");
	const swba::Summary s = solve_bal(bal, {});
	EXPECT_EQ(s.termination, swba::TerminationType::Failure);
	EXPECT_EQ(s.message, "every factor dropped at the initial values: nothing to fit");
	EXPECT_EQ(s.num_dropped_factors, 1);
	EXPECT_FALSE(s.is_solution_usable());

	const std::string path = ::testing::TempDir() + "swba_bal_allpz0.txt";
	const std::string solution = ::testing::TempDir() + "swba_bal_allpz0_solution.txt";
	{
		std::ofstream f(path);
		f << text;
	}
	std::remove(solution.c_str());
	swba::apps::BalAppOptions o;
	o.problem_path = path;
	o.write_problem = solution;
	std::ostringstream out, log;
	try
	{
		swba::apps::run_bal_app(o, out, log);
		ADD_FAILURE() << "no exception";
	}
	catch (const std::runtime_error& e)
	{
		EXPECT_STREQ(e.what(), "optimisation failed: every factor dropped at the initial values: nothing to fit");
	}
	EXPECT_NE(out.str().find("Termination: FAILURE"), std::string::npos) << out.str();
	EXPECT_FALSE(std::ifstream(solution).good()) << "a failed solve wrote its solution";
	std::remove(path.c_str());
}
