#include <gtest/gtest.h>
#include <swba/linear/marginal.h>

#include <Eigen/Dense>
#include <cmath>
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

namespace
{
/** H = AᵀA (n × n) with a known null space N (n × k): the rows of A are orthogonal to N. Columns scaled
 * by `scales` (spanning many orders of magnitude, as poses and landmarks in a prior do). */
struct RankDeficient
{
	Eigen::MatrixXd H, N;
	Eigen::VectorXd b;  ///< in the range of H (b = Aᵀr)
};

RankDeficient rank_deficient(std::mt19937& rng, int n, int k, const Eigen::VectorXd& scales)
{
	std::normal_distribution<double> g(0, 1);
	Eigen::MatrixXd N0(n, k), A0(2 * n, n);
	for (int i = 0; i < n; i++)
		for (int j = 0; j < k; j++) N0(i, j) = g(rng);
	for (int i = 0; i < A0.rows(); i++)
		for (int j = 0; j < n; j++) A0(i, j) = g(rng);
	const Eigen::MatrixXd Q = N0.householderQr().householderQ() * Eigen::MatrixXd::Identity(n, k);
	A0 -= (A0 * Q) * Q.transpose();  // rows ⟂ span(N0)
	Eigen::VectorXd r(A0.rows());
	for (int i = 0; i < r.size(); i++) r[i] = g(rng);
	// Scaling the coordinates x = S y: A = A0 S⁻¹ has the null space S N0.
	const Eigen::MatrixXd A = A0 * scales.cwiseInverse().asDiagonal();
	RankDeficient out;
	out.H = A.transpose() * A;
	out.N = scales.asDiagonal() * Q;
	out.b = A.transpose() * r;
	return out;
}
}  // namespace

// The square root of a rank-deficient prior keeps the range and drops the null space: rank n − k,
// JᵀJ = H and −Jᵀe = b (b in the range), J N = 0; the returned H and b are those of (J, e). The
// coordinates' scales span 4 orders of magnitude (H: 8), so that the pivots left after the range are
// rounding noise of either sign (a factorisation that is not rank-revealing keeps some of them).
TEST(Marginalization, RankDeficientPriorKeepsTheRangeAndDropsTheNullSpace)
{
	std::mt19937 rng(3);
	const int n = 30, k = 6;
	Eigen::VectorXd scales(n);
	for (int i = 0; i < n; i++) scales[i] = std::pow(10.0, (i % 5) - 2);
	for (int trial = 0; trial < 20; trial++)
	{
		const RankDeficient p = rank_deficient(rng, n, k, scales);
		std::vector<int> all(n);
		for (int i = 0; i < n; i++) all[i] = i;
		const auto m = marginalize(p.H, p.b, all, {});
		EXPECT_EQ(m.rank, n - k) << "trial " << trial;
		const double h = p.H.norm();
		EXPECT_LT((m.J.transpose() * m.J - p.H).norm(), 1e-9 * h) << "trial " << trial;
		EXPECT_LT((m.J * p.N).norm(), 1e-9 * m.J.norm() * p.N.norm()) << "trial " << trial;
		EXPECT_LT((m.J.transpose() * m.e + p.b).norm(), 1e-9 * p.b.norm()) << "trial " << trial;
		EXPECT_LT((m.H - m.J.transpose() * m.J).norm(), 1e-14 * h) << "trial " << trial;
		EXPECT_LT((m.b + m.J.transpose() * m.e).norm(), 1e-14 * p.b.norm()) << "trial " << trial;
	}
}

TEST(Marginalization, RejectsOverlappingIndexSets)
{
	const Eigen::MatrixXd H = seed000_chain_H();
	EXPECT_THROW(marginalize(H, Eigen::VectorXd::Zero(3), {0, 1}, {1}), std::invalid_argument);
	EXPECT_THROW(marginalize(H, Eigen::VectorXd::Zero(3), {0, 5}, {1}), std::invalid_argument);
}

// marginalize_leading (the window's marginalisation): the same prior as swba::marginalize when H* is
// positive definite (Cholesky square root), and, when H* is rank-deficient like an inverse-depth anchor
// pose (pivoted-Cholesky square root), the truncated eigen-decomposition of a Schur complement the test
// computes itself.
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
		// Reference computed independently: the Schur complement with an exact inverse of H_oo (the
		// odometry rows make it positive definite) and the eigen-decomposition of H*, truncated.
		const Eigen::MatrixXd K = H.topRightCorner(12, 6) * H.bottomRightCorner(6, 6).inverse();
		const Eigen::MatrixXd Hs = H.topLeftCorner(12, 12) - K * H.bottomLeftCorner(6, 12);
		const Eigen::VectorXd bs = b.head(12) - K * b.tail(6);
		Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(0.5 * (Hs + Hs.transpose()));
		const Eigen::VectorXd ev = es.eigenvalues();
		Eigen::VectorXd kept = Eigen::VectorXd::Zero(12);
		int rank = 0;
		for (int i = 0; i < 12; i++)
			if (ev[i] > 1e-12 * ev.maxCoeff())
			{
				kept[i] = ev[i];
				rank++;
			}
		ASSERT_EQ(rank, 6);
		const Eigen::MatrixXd Href = es.eigenvectors() * kept.asDiagonal() * es.eigenvectors().transpose();
		EXPECT_LT((got.J.transpose() * got.J - Href).norm(), 1e-9 * Href.norm());
		EXPECT_LT((got.J.transpose() * got.e + bs).norm(), 1e-9 * bs.norm());
		// Its null space is the reference's.
		const Eigen::MatrixXd Nref = es.eigenvectors().leftCols(6);
		EXPECT_LT((got.J * Nref).norm(), 1e-9 * got.J.norm());
	}
}
