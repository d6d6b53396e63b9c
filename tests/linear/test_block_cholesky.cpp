#include <gtest/gtest.h>
#include <swba/linear/block_cholesky.h>
#include <swba/linear/selected_inverse.h>

#include <Eigen/Dense>
#include <random>
#include <stdexcept>

using namespace swba;

namespace
{
struct RandomBlockSystem
{
	BlockPattern pattern;
	Eigen::MatrixXd A;
	std::vector<std::vector<double>> blocks;
};

RandomBlockSystem make_system(int nblocks, unsigned seed)
{
	std::mt19937 rng(seed);
	std::normal_distribution<double> N(0, 1);
	RandomBlockSystem s;
	for (int i = 0; i < nblocks; i++) s.pattern.block_sizes.push_back(i % 3 == 0 ? 6 : (i % 3 == 1 ? 3 : 1));
	const auto off = s.pattern.offsets();
	const int n = off.back();
	// Sparse SPD matrix: chain + a few random links, diagonally dominant.
	Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n, n);
	std::vector<std::pair<int, int>> pairs;
	for (int i = 0; i < nblocks; i++)
	{
		pairs.push_back({i, i});
		if (i + 1 < nblocks) pairs.push_back({i, i + 1});
		if (i + 5 < nblocks && i % 4 == 0) pairs.push_back({i, i + 5});
	}
	std::sort(pairs.begin(), pairs.end());
	for (auto [i, j] : pairs)
	{
		if (i == j) continue;
		for (int r = 0; r < s.pattern.block_sizes[i]; r++)
			for (int c = 0; c < s.pattern.block_sizes[j]; c++)
			{
				const double v = N(rng);
				A(off[i] + r, off[j] + c) = v;
				A(off[j] + c, off[i] + r) = v;
			}
	}
	for (int i = 0; i < n; i++) A(i, i) = A.row(i).cwiseAbs().sum() + 1.0 + std::abs(N(rng));
	s.A = A;
	s.pattern.upper_blocks = pairs;
	for (auto [i, j] : pairs)
	{
		std::vector<double> B;
		for (int r = 0; r < s.pattern.block_sizes[i]; r++)
			for (int c = 0; c < s.pattern.block_sizes[j]; c++) B.push_back(A(off[i] + r, off[j] + c));
		s.blocks.push_back(B);
	}
	return s;
}
}  // namespace

TEST(BlockCholesky, DenseAndCholmodEqualEigenDenseSolve)
{
	const auto s = make_system(40, 3);
	std::vector<const double*> blocks;
	for (const auto& b : s.blocks) blocks.push_back(b.data());
	Eigen::VectorXd rhs = Eigen::VectorXd::LinSpaced(s.A.rows(), -1.0, 2.0);
	const Eigen::VectorXd ref = s.A.ldlt().solve(rhs);
	for (bool sparse : {false, true})
	{
		auto chol = sparse ? BlockCholesky::sparse(s.pattern) : BlockCholesky::dense(s.pattern);
		ASSERT_TRUE(chol->factorize(blocks));
		Eigen::VectorXd x = rhs;
		chol->solve(x.data());
		EXPECT_LT((x - ref).norm(), 1e-9 * ref.norm()) << (sparse ? "cholmod" : "dense");
		EXPECT_EQ(chol->is_sparse(), sparse);
	}
}

TEST(BlockCholesky, RefactorizeWithNewValuesOnSamePattern)
{
	auto s = make_system(25, 11);
	auto chol = BlockCholesky::sparse(s.pattern);
	for (int round = 0; round < 2; round++)
	{
		std::vector<const double*> blocks;
		for (const auto& b : s.blocks) blocks.push_back(b.data());
		ASSERT_TRUE(chol->factorize(blocks));
		Eigen::VectorXd x = Eigen::VectorXd::Ones(s.A.rows());
		chol->solve(x.data());
		EXPECT_LT((s.A * x - Eigen::VectorXd::Ones(s.A.rows())).norm(), 1e-9);
		s = make_system(25, 12);  // same pattern (same sizes and pairs), new values
	}
}

TEST(BlockCholesky, ReportsNotPositiveDefinite)
{
	auto s = make_system(10, 5);
	for (auto& b : s.blocks) b.assign(b.size(), 0.0);  // zero matrix
	std::vector<const double*> blocks;
	for (const auto& b : s.blocks) blocks.push_back(b.data());
	EXPECT_FALSE(BlockCholesky::dense(s.pattern)->factorize(blocks));
	EXPECT_FALSE(BlockCholesky::sparse(s.pattern)->factorize(blocks));
}

TEST(BlockCholesky, SelectedInverseEqualsTheDenseInverseOnTheFactorsPattern)
{
	const auto s = make_system(40, 3);
	std::vector<const double*> blocks;
	for (const auto& b : s.blocks) blocks.push_back(b.data());
	auto dense = BlockCholesky::dense(s.pattern);
	ASSERT_TRUE(dense->factorize(blocks));
	const int n = static_cast<int>(s.A.rows());
	EXPECT_EQ(dense->selected_inverse(n), nullptr);
	auto chol = BlockCholesky::sparse(s.pattern);
	ASSERT_TRUE(chol->factorize(blocks));
	EXPECT_EQ(chol->selected_inverse(1), nullptr);  // one column: its solve is cheaper than the pass
	const auto inverse = chol->selected_inverse(n);
	ASSERT_NE(inverse, nullptr);
	ASSERT_EQ(inverse->dim(), s.A.rows());
	const Eigen::MatrixXd want = s.A.inverse();
	// Every entry of every block of A is in the pattern (CHOLMOD permutes the rows: the map back is tested too).
	const auto off = s.pattern.offsets();
	for (auto [i, j] : s.pattern.upper_blocks)
		for (int r = off[i]; r < off[i + 1]; r++)
			for (int c = off[j]; c < off[j + 1]; c++)
			{
				double v = 0, w = 0;
				ASSERT_TRUE(inverse->find(r, c, v)) << r << ", " << c;
				ASSERT_TRUE(inverse->find(c, r, w));
				EXPECT_NEAR(v, want(r, c), 1e-12 * want.norm()) << r << ", " << c;
				EXPECT_EQ(v, w);
			}
	double v = 0;
	EXPECT_FALSE(inverse->find(-1, 0, v));
	EXPECT_FALSE(inverse->find(0, static_cast<int>(s.A.rows()), v));
}

TEST(SelectedInverse, RejectsAPatternThatIsNotACholeskyFactors)
{
	// 3×3, L = [2 0 0; 1 2 0; 1 0 2]: column 0 holds rows 1 and 2, so (2, 1) is fill and must be stored.
	const int begin[] = {0, 3, 4, 5};
	const int rows[] = {0, 1, 2, 1, 2};
	const double values[] = {2, 1, 1, 2, 2};
	EXPECT_THROW(SelectedInverse(3, begin, rows, values, nullptr), std::invalid_argument);
	const int unsorted[] = {0, 2, 1, 1, 2};
	const int begin_filled[] = {0, 3, 5, 6};
	const int rows_filled[] = {0, 1, 2, 1, 2, 2};
	const double values_filled[] = {2, 1, 1, 2, 0, 2};
	EXPECT_THROW(SelectedInverse(3, begin, unsorted, values, nullptr), std::invalid_argument);
	// With the fill entry stored (as a zero), the inverse of L Lᵀ on the pattern.
	const SelectedInverse z(3, begin_filled, rows_filled, values_filled, nullptr);
	Eigen::Matrix3d L;
	L << 2, 0, 0, 1, 2, 0, 1, 0, 2;
	const Eigen::Matrix3d want = (L * L.transpose()).inverse();
	for (int r = 0; r < 3; r++)
		for (int c = 0; c < 3; c++)
		{
			double v = 0;
			ASSERT_TRUE(z.find(r, c, v));
			EXPECT_NEAR(v, want(r, c), 1e-14);
		}
}
