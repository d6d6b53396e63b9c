#include <swba/core/chi2.h>

#include <boost/math/distributions/chi_squared.hpp>

#include <cmath>
#include <stdexcept>
#include <string>

namespace swba
{
namespace
{
boost::math::chi_squared distribution(int dof)
{
	if (dof < 1) throw std::invalid_argument("chi2: degrees of freedom must be >= 1, got " + std::to_string(dof));
	return boost::math::chi_squared(static_cast<double>(dof));
}
}  // namespace

double chi2_cdf(double x, int dof)
{
	const auto d = distribution(dof);
	if (std::isnan(x)) throw std::invalid_argument("chi2: x is NaN");
	if (!(x > 0)) return 0.0;
	if (std::isinf(x)) return 1.0;
	return boost::math::cdf(d, x);
}

double chi2_quantile(double p, int dof)
{
	if (!(p > 0 && p < 1)) throw std::invalid_argument("chi2: probability must be in (0, 1), got " + std::to_string(p));
	return boost::math::quantile(distribution(dof), p);
}
}  // namespace swba
