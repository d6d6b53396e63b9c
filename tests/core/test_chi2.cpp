// χ² CDF and quantile against closed forms and table values.
#include <swba/core/chi2.h>

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace
{
TEST(Chi2, CdfMatchesClosedForms)
{
	for (double x : {0.01, 0.5, 2.0, 7.0, 20.0, 60.0})
	{
		EXPECT_NEAR(swba::chi2_cdf(x, 2), 1.0 - std::exp(-0.5 * x), 1e-13) << x;  // exponential
		EXPECT_NEAR(swba::chi2_cdf(x, 1), std::erf(std::sqrt(0.5 * x)), 1e-13) << x;
		const double k3 = std::erf(std::sqrt(0.5 * x)) - std::sqrt(2.0 * x / M_PI) * std::exp(-0.5 * x);
		EXPECT_NEAR(swba::chi2_cdf(x, 3), k3, 1e-13) << x;
	}
	EXPECT_EQ(swba::chi2_cdf(0.0, 3), 0.0);
}

TEST(Chi2, QuantileMatchesTables)
{
	EXPECT_NEAR(swba::chi2_quantile(0.999, 2), -2.0 * std::log(0.001), 1e-9);
	EXPECT_NEAR(swba::chi2_quantile(0.999, 3), 16.266236, 1e-5);
	EXPECT_NEAR(swba::chi2_quantile(0.99, 3), 11.344867, 1e-5);
	EXPECT_NEAR(swba::chi2_quantile(0.95, 3), 7.814728, 1e-5);
	EXPECT_NEAR(swba::chi2_quantile(0.95, 1), 3.841459, 1e-5);
	EXPECT_NEAR(swba::chi2_quantile(0.5, 30), 29.336, 1e-3);  // table: 29.336
	for (double p : {0.001, 0.3, 0.9, 0.99999})
		EXPECT_NEAR(swba::chi2_cdf(swba::chi2_quantile(p, 3), 3), p, 1e-10) << p;
}

TEST(Chi2, RejectsBadArguments)
{
	EXPECT_THROW(swba::chi2_quantile(1.0, 3), std::invalid_argument);
	EXPECT_THROW(swba::chi2_quantile(0.0, 3), std::invalid_argument);
	EXPECT_THROW(swba::chi2_quantile(0.9, 0), std::invalid_argument);
	EXPECT_THROW(swba::chi2_cdf(1.0, 0), std::invalid_argument);
}
}  // namespace
