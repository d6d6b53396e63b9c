#include <gtest/gtest.h>
#include <swba/linear/marginal.h>

#include <Eigen/Dense>
#include <random>

using namespace swba;

// Seed 000's TestMarginalize: chain x1 - x2 - x3 with σ = 0.1 (x1-x2), 0.2 (prior on x2), 0.3 (x2-x3).
static Eigen::MatrixXd seed000_chain_H()
{
	const double a = 1.0 / (0.1 * 0.1), c = 1.0 / (0.2 * 0.2), d = 1.0 / (0.3 * 0.3);
	Eigen::MatrixXd H(3, 3);
	H << a, -a, 0, -a, a + c + d, -d, 0, -d, d;
	return H;
}

TEST(Marginalization, Seed000ChainBeforeMarginalisationMatchesPrintedH)
{
	const Eigen::MatrixXd H = seed000_chain_H();
	EXPECT_NEAR(H(0, 0), 100, 5e-4);
	EXPECT_NEAR(H(1, 1), 136.111, 5e-4);
	EXPECT_NEAR(H(1, 2), -11.1111, 5e-5);
	EXPECT_NEAR(H(2, 2), 11.1111, 5e-5);
}

TEST(Marginalization, Seed000MiddleVariableGivesPrintedPrior)
{
	const Eigen::MatrixXd H = seed000_chain_H();
	const Eigen::VectorXd b = Eigen::VectorXd::Zero(3);
	const auto m = marginalize(H, b, {0, 2}, {1});
	ASSERT_EQ(m.H.rows(), 2);
	// Printed digits of seed 000: [[26.5306, -8.16327], [-8.16327, 10.2041]].
	EXPECT_NEAR(m.H(0, 0), 26.5306, 5e-5);
	EXPECT_NEAR(m.H(0, 1), -8.16327, 5e-6);
	EXPECT_NEAR(m.H(1, 0), -8.16327, 5e-6);
	EXPECT_NEAR(m.H(1, 1), 10.2041, 5e-5);
}

TEST(Marginalization, SquareRootFormReproducesHAndB)
{
	const Eigen::MatrixXd H = seed000_chain_H();
	Eigen::VectorXd b(3);
	b << 0.3, -1.2, 2.5;
	const auto m = marginalize(H, b, {0, 2}, {1});
	EXPECT_EQ(m.rank, 2);
	EXPECT_LT((m.J.transpose() * m.J - m.H).norm(), 1e-10 * m.H.norm());
	EXPECT_LT((-m.J.transpose() * m.e - m.b).norm(), 1e-10 * std::max(1.0, m.b.norm()));
	// b* = b_k - H_km H_mm^-1 b_m, computed independently.
	Eigen::Vector2d bstar(b[0] - H(0, 1) / H(1, 1) * b[1], b[2] - H(2, 1) / H(1, 1) * b[1]);
	EXPECT_LT((m.b - bstar).norm(), 1e-12);
}

TEST(Marginalization, EqualsInverseOfCovarianceBlockForRandomSpdMatrix)
{
	std::mt19937 rng(7);
	std::normal_distribution<double> N(0, 1);
	const int n = 9;
	Eigen::MatrixXd A(n + 3, n);
	for (int i = 0; i < A.rows(); i++)
		for (int j = 0; j < n; j++) A(i, j) = N(rng);
	const Eigen::MatrixXd H = A.transpose() * A;
	Eigen::VectorXd b(n);
	for (int i = 0; i < n; i++) b[i] = N(rng);
	const std::vector<int> keep{0, 3, 4, 8}, marg{1, 2, 5, 6, 7};
	const auto m = marginalize(H, b, keep, marg);
	const Eigen::MatrixXd cov = H.inverse();
	Eigen::MatrixXd cov_kk(4, 4);
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++) cov_kk(i, j) = cov(keep[i], keep[j]);
	EXPECT_LT((m.H - cov_kk.inverse()).norm(), 1e-9 * m.H.norm());
	// The marginal mean: H* δk = b* equals the kept part of the full solution H δ = b.
	const Eigen::VectorXd full = H.ldlt().solve(b);
	const Eigen::VectorXd part = m.H.ldlt().solve(m.b);
	for (int i = 0; i < 4; i++) EXPECT_NEAR(part[i], full[keep[i]], 1e-9 * full.norm());
}

TEST(Marginalization, RankDeficientPriorIsTruncated)
{
	// Two relative constraints between three scalars: a 1-dim null space (common translation).
	Eigen::MatrixXd J(2, 3);
	J << -1, 1, 0, 0, -1, 1;
	const Eigen::MatrixXd H = J.transpose() * J;
	const auto m = marginalize(H, Eigen::VectorXd::Zero(3), {0, 1, 2}, {});
	EXPECT_EQ(m.rank, 2);
	EXPECT_LT((m.J.transpose() * m.J - H).norm(), 1e-12);
	EXPECT_LT((m.J * Eigen::Vector3d::Ones()).norm(), 1e-12);
}

TEST(Marginalization, RejectsOverlappingIndexSets)
{
	const Eigen::MatrixXd H = seed000_chain_H();
	EXPECT_THROW(marginalize(H, Eigen::VectorXd::Zero(3), {0, 1}, {1}), std::invalid_argument);
	EXPECT_THROW(marginalize(H, Eigen::VectorXd::Zero(3), {0, 5}, {1}), std::invalid_argument);
}
