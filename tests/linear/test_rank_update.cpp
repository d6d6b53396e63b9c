// lower_rank_update: every SIMD level this CPU runs against a plain triple loop, on strided blocks of
// awkward sizes (not multiples of any packet width), mixed signs; the strict upper triangle untouched.
#include <gtest/gtest.h>
#include <swba/linear/rank_update.h>

#include <algorithm>
#include <cstdlib>

using namespace swba;

namespace
{
class RankUpdateLevel : public ::testing::TestWithParam<SimdLevel>
{
   protected:
	void SetUp() override
	{
		const auto& levels = available_simd_levels();
		if (std::find(levels.begin(), levels.end(), GetParam()) == levels.end())
			GTEST_SKIP() << enum_name(GetParam()) << " is not available in this build on this CPU";
	}
};

TEST_P(RankUpdateLevel, MatchesTripleLoopOnLowerTriangleOnly)
{
	std::srand(7);
	for (const auto& [n, k] : std::vector<std::pair<int, int>>{{1, 1}, {5, 3}, {37, 6}, {67, 24}, {131, 29}})
	{
		// n × n blocks of larger matrices: the kernels must honour the outer strides.
		Eigen::MatrixXd C_storage = Eigen::MatrixXd::Random(n + 5, n + 3);
		Eigen::MatrixXd U_storage = Eigen::MatrixXd::Random(n + 7, k + 2);
		Eigen::VectorXd sign(k);
		for (int q = 0; q < k; q++) sign[q] = (q % 3 == 1) ? -1.0 : 0.5 + q;
		const Eigen::MatrixXd before = C_storage;
		auto C = C_storage.block(2, 1, n, n);
		const auto U = U_storage.block(3, 2, n, k);

		lower_rank_update(GetParam(), C, U, sign);

		double worst = 0;
		for (int j = 0; j < n; j++)
			for (int i = 0; i < n; i++)
			{
				if (i < j)
				{
					EXPECT_EQ(C(i, j), before(2 + i, 1 + j)) << "upper triangle written at " << i << "," << j;
					continue;
				}
				long double ref = before(2 + i, 1 + j);
				for (int q = 0; q < k; q++) ref += static_cast<long double>(U(i, q)) * sign[q] * U(j, q);
				worst = std::max(worst, std::abs(static_cast<double>(ref) - C(i, j)));
			}
		EXPECT_LT(worst, 1e-12 * k) << "n = " << n << ", k = " << k;
		// Outside the block nothing moves.
		Eigen::MatrixXd outside = C_storage;
		outside.block(2, 1, n, n) = before.block(2, 1, n, n);
		EXPECT_EQ(outside, before) << "written outside the block, n = " << n;
	}
}

INSTANTIATE_TEST_SUITE_P(Levels, RankUpdateLevel,
						 ::testing::Values(SimdLevel::Baseline, SimdLevel::Avx2, SimdLevel::Avx512),
						 [](const auto& level) { return enum_name(level.param); });

TEST(RankUpdate, RunsTheWidestAvailableLevelByDefault)
{
	if (std::getenv("SWBA_SIMD") != nullptr) GTEST_SKIP() << "SWBA_SIMD is set";
	const auto& levels = available_simd_levels();
	ASSERT_FALSE(levels.empty());
	EXPECT_EQ(levels.front(), SimdLevel::Baseline);
	EXPECT_EQ(active_simd_level(), levels.back());
}

TEST(RankUpdate, RejectsMismatchedShapes)
{
	Eigen::MatrixXd C = Eigen::MatrixXd::Zero(4, 4), U = Eigen::MatrixXd::Ones(4, 2);
	Eigen::MatrixXd rect = Eigen::MatrixXd::Zero(4, 3), U3 = Eigen::MatrixXd::Ones(3, 2);
	EXPECT_THROW(lower_rank_update(C, U, Eigen::VectorXd::Ones(3)), std::invalid_argument);
	EXPECT_THROW(lower_rank_update(rect, U, Eigen::VectorXd::Ones(2)), std::invalid_argument);
	EXPECT_THROW(lower_rank_update(C, U3, Eigen::VectorXd::Ones(2)), std::invalid_argument);
	lower_rank_update(C, U, Eigen::VectorXd::Ones(2));
	EXPECT_EQ(C(3, 0), 2.0);
	EXPECT_EQ(C(0, 3), 0.0);
}
}  // namespace
