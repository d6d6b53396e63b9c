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
	const auto got = swba::marginalize_leading(H, b, num_keep, 1e-12);
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
		const auto got = swba::marginalize_leading(H, b, 12, 1e-12);
		EXPECT_EQ(got.rank, 6);
		expect_same_prior(H, b, 12);
	}
}
