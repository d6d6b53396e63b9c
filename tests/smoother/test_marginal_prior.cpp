// MarginalPrior: the stored information H = JᵀJ, b = −Jᵀe stays that of (J, e) when variables are added
// (zero columns) and when a variable is replaced by a first-order change of variables; the prior's
// factor follows install / uninstall.
#include <gtest/gtest.h>
#include <swba/linear/marginal.h>
#include <swba/smoother/marginal_prior.h>

#include <mrpt/poses/CPose3D.h>

#include <random>

using namespace swba;
using namespace swba::smoother;

namespace
{
Eigen::MatrixXd random_matrix(std::mt19937& rng, int rows, int cols)
{
	std::normal_distribution<double> N(0, 1);
	Eigen::MatrixXd A(rows, cols);
	for (int i = 0; i < rows; i++)
		for (int j = 0; j < cols; j++) A(i, j) = N(rng);
	return A;
}

/** A full-rank marginal over `dim` coordinates (marginalize_leading of a random positive definite H). */
MarginalizationResult random_marginal(std::mt19937& rng, int dim)
{
	const Eigen::MatrixXd A = random_matrix(rng, 2 * dim, dim);
	return marginalize_leading(A.transpose() * A, random_matrix(rng, dim, 1).col(0), dim, 1e-12);
}

void expect_information_of_square_root(const MarginalPrior& p)
{
	ASSERT_TRUE(p.has_information());
	const double scale = p.H().norm();
	EXPECT_LT((p.H() - p.J().transpose() * p.J()).norm(), 1e-12 * scale);
	EXPECT_LT((p.b() + p.J().transpose() * p.e()).norm(), 1e-12 * std::max(1.0, p.b().norm()));
}
}  // namespace

TEST(MarginalPrior, InformationFollowsAddedVariablesAndChangeOfVariables)
{
	std::mt19937 rng(5);
	Problem problem;
	const VariableId a = problem.add_pose(mrpt::poses::CPose3D(1, 2, 3, 0.1, 0.2, 0.3));
	const VariableId b = problem.add_pose(mrpt::poses::CPose3D(-1, 0, 2, -0.2, 0.1, 0.0));
	const VariableId l = problem.add_variable(Eigen::Vector3d(0.3, -0.1, 0.5), euclidean_manifold(3));
	const VariableId l2 = problem.add_variable(Eigen::Vector3d(0.2, 0.1, 0.4), euclidean_manifold(3));

	MarginalPrior prior;
	prior.reset(problem, {a, l}, random_marginal(rng, 9));
	ASSERT_TRUE(prior.installed());
	EXPECT_EQ(prior.rank(), 9);
	expect_information_of_square_root(prior);

	// b enters with zero columns: J, H and b are extended with zeros.
	const int ib = prior.add_variable(problem, b);
	EXPECT_EQ(ib, 2);
	EXPECT_EQ(prior.column_of(problem, ib), 9);
	EXPECT_EQ(prior.J().rightCols(6).norm(), 0.0);
	expect_information_of_square_root(prior);

	VariableChange c;
	c.old_var = l;
	c.new_var = l2;
	c.new_x_lin = {0.2, 0.1, 0.4};
	c.D = random_matrix(rng, 3, 3);
	c.H_new = random_matrix(rng, 3, 3);
	c.H_others = {{a, random_matrix(rng, 3, 6)}, {b, random_matrix(rng, 3, 6)}};
	const Eigen::MatrixXd J_before = prior.J();
	prior.change_variable(problem, c);
	const Eigen::MatrixXd J_old = J_before.middleCols(6, 3);
	EXPECT_LT((prior.J().middleCols(6, 3) - J_old * c.D * c.H_new).norm(), 1e-12 * J_old.norm());
	EXPECT_LT((prior.J().middleCols(9, 6) - J_old * c.D * c.H_others[1].second).norm(), 1e-12 * J_old.norm());
	EXPECT_EQ(prior.variables(), (std::vector<VariableId>{a, l2, b}));
	EXPECT_EQ(prior.linearization_points()[1], c.new_x_lin);
	expect_information_of_square_root(prior);

	// install() replaces the factor (now over a, l2, b); uninstall() removes it.
	prior.install(problem);
	ASSERT_TRUE(prior.installed());
	EXPECT_EQ(problem.factor(prior.factor()).variables, prior.variables());
	EXPECT_EQ(problem.num_factors(), 1u);
	prior.uninstall(problem);
	EXPECT_FALSE(prior.installed());
	EXPECT_EQ(problem.num_factors(), 0u);
}

TEST(MarginalPrior, ZeroRankMarginalClearsThePrior)
{
	Problem problem;
	const VariableId a = problem.add_pose(mrpt::poses::CPose3D());
	MarginalPrior prior;
	prior.reset(problem, {a}, MarginalizationResult{});
	EXPECT_FALSE(prior.installed());
	EXPECT_EQ(prior.rank(), 0);
	EXPECT_TRUE(prior.variables().empty());
}
