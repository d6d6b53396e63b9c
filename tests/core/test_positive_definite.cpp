// Nearest positive-definite matrix by eigenvalue clipping (swba/core/positive_definite.h).
#include <gtest/gtest.h>
#include <swba/core/positive_definite.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <random>
#include <stdexcept>

namespace
{
using Eigen::MatrixXd;
using swba::kPositiveDefiniteRelativeFloor;

MatrixXd random_matrix(int n, std::mt19937& rng)
{
	std::normal_distribution<double> g;
	MatrixXd a(n, n);
	for (int r = 0; r < n; r++)
		for (int c = 0; c < n; c++) a(r, c) = g(rng);
	return a;
}

bool is_positive_definite(const MatrixXd& a) { return Eigen::LLT<MatrixXd>(a).info() == Eigen::Success; }

TEST(NearestPositiveDefinite, DiagonalNegativeEntryIsRaisedToTheRelativeFloor)
{
	// diag(4, −1): λ_max = 4, floor = 1e-6 · 4; the eigenvectors are the axes, so the result is
	// diag(4, 4e-6).
	const MatrixXd a = Eigen::Vector2d(4, -1).asDiagonal();
	const auto r = swba::repair_positive_definite(a);
	EXPECT_TRUE(r.repaired);
	EXPECT_EQ(r.clipped, 1);
	EXPECT_DOUBLE_EQ(r.min_eigenvalue, -1);
	EXPECT_DOUBLE_EQ(r.max_eigenvalue, 4);
	const double floor = kPositiveDefiniteRelativeFloor * 4;
	EXPECT_NEAR(r.matrix(0, 0), 4, 1e-15);
	EXPECT_NEAR(r.matrix(1, 1), floor, 1e-20);
	EXPECT_NEAR(r.matrix(0, 1), 0, 1e-20);
	EXPECT_EQ(r.matrix(0, 1), r.matrix(1, 0));
}

TEST(NearestPositiveDefinite, OffDiagonalCaseMatchesTheHandComputedRebuild)
{
	// [[1, 2], [2, 1]]: λ = 3 on (1, 1)/√2, λ = −1 on (1, −1)/√2. Clipping −1 to 3e-6 gives
	// 3·vvᵀ + 3e-6·wwᵀ = [[1.5 + 1.5e-6, 1.5 − 1.5e-6], [1.5 − 1.5e-6, 1.5 + 1.5e-6]].
	MatrixXd a(2, 2);
	a << 1, 2, 2, 1;
	const MatrixXd m = swba::nearest_positive_definite(a);
	const double f = kPositiveDefiniteRelativeFloor * 3 / 2;
	EXPECT_NEAR(m(0, 0), 1.5 + f, 1e-14);
	EXPECT_NEAR(m(1, 1), 1.5 + f, 1e-14);
	EXPECT_NEAR(m(0, 1), 1.5 - f, 1e-14);
	EXPECT_EQ(m(0, 1), m(1, 0));
	EXPECT_TRUE(is_positive_definite(m));
}

TEST(NearestPositiveDefinite, RandomIndefiniteMatricesBecomeSymmetricPositiveDefiniteWithTheFloor)
{
	std::mt19937 rng(7);
	for (int trial = 0; trial < 200; trial++)
	{
		const int n = trial % 2 ? 6 : 3;
		// Not symmetric; indefinite for sure: a positive and a negative diagonal entry (xᵀSx = S_ii).
		MatrixXd a = random_matrix(n, rng) * (trial + 1);
		a(0, 0) = std::abs(a(0, 0)) + 1;
		a(n - 1, n - 1) = -std::abs(a(n - 1, n - 1)) - 1;
		const auto r = swba::repair_positive_definite(a);
		ASSERT_TRUE(r.repaired);
		EXPECT_TRUE((r.matrix.array() == r.matrix.transpose().array()).all());  // exactly symmetric
		EXPECT_TRUE(is_positive_definite(r.matrix));
		const Eigen::VectorXd lambda = Eigen::SelfAdjointEigenSolver<MatrixXd>(r.matrix).eigenvalues();
		const double floor = kPositiveDefiniteRelativeFloor * r.max_eigenvalue;
		EXPECT_GE(lambda(0), floor * (1 - 1e-6));
		// Nearer (Frobenius) to the symmetric part than the other simple repair, a diagonal shift.
		const MatrixXd s = 0.5 * (a + a.transpose());
		const MatrixXd shifted = s + (floor - r.min_eigenvalue) * MatrixXd::Identity(n, n);
		EXPECT_LE((r.matrix - s).norm(), (shifted - s).norm() * (1 + 1e-12));
	}
}

TEST(NearestPositiveDefinite, PositiveDefiniteInputIsReturnedBitIdentical)
{
	std::mt19937 rng(11);
	for (int trial = 0; trial < 50; trial++)
	{
		const MatrixXd b = random_matrix(6, rng);
		// Well or badly conditioned, a valid information is never altered.
		MatrixXd a = b * b.transpose() + (trial % 2 ? 1e-9 : 1.0) * MatrixXd::Identity(6, 6);
		a = 0.5 * (a + a.transpose());  // exactly symmetric, as the reader builds informations
		const auto r = swba::repair_positive_definite(a);
		EXPECT_FALSE(r.repaired);
		EXPECT_EQ(r.clipped, 0);
		EXPECT_TRUE((r.matrix.array() == a.array()).all());
	}
}

TEST(NearestPositiveDefinite, ScalesWithTheMatrix)
{
	std::mt19937 rng(3);
	const MatrixXd a = random_matrix(6, rng);
	const MatrixXd m1 = swba::nearest_positive_definite(a);
	const MatrixXd m2 = swba::nearest_positive_definite(1e5 * a);
	EXPECT_TRUE((1e5 * m1).isApprox(m2, 1e-12));
}

TEST(NearestPositiveDefinite, NoPositiveEigenvalueIsAClearError)
{
	EXPECT_THROW(swba::nearest_positive_definite(Eigen::Vector3d(-1, -2, -3).asDiagonal().toDenseMatrix()),
				 std::domain_error);
	try
	{
		swba::nearest_positive_definite(MatrixXd::Zero(3, 3));
		FAIL() << "no exception";
	}
	catch (const std::domain_error& e)
	{
		EXPECT_NE(std::string(e.what()).find("no positive eigenvalue"), std::string::npos) << e.what();
	}
}

TEST(NearestPositiveDefinite, InvalidArgumentsAreRejected)
{
	EXPECT_THROW(swba::nearest_positive_definite(MatrixXd::Identity(2, 3)), std::invalid_argument);
	EXPECT_THROW(swba::nearest_positive_definite(MatrixXd::Identity(2, 2), 0), std::invalid_argument);
	EXPECT_THROW(swba::nearest_positive_definite(MatrixXd::Identity(2, 2), 2), std::invalid_argument);
	MatrixXd nan = MatrixXd::Identity(2, 2);
	nan(0, 1) = std::nan("");
	EXPECT_THROW(swba::nearest_positive_definite(nan), std::invalid_argument);
}
}  // namespace
