#include <swba/core/chi2.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace swba
{
namespace
{
/** P(a, x) by its power series, for x < a + 1. */
double gamma_p_series(double a, double x)
{
	double term = 1.0 / a, sum = term;
	for (int n = 1; n < 1000 && std::abs(term) > std::abs(sum) * 1e-16; n++)
	{
		term *= x / (a + n);
		sum += term;
	}
	return sum * std::exp(-x + a * std::log(x) - std::lgamma(a));
}

/** Q(a, x) = 1 − P(a, x) by its continued fraction (modified Lentz), for x ≥ a + 1. */
double gamma_q_fraction(double a, double x)
{
	constexpr double tiny = 1e-300;
	double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
	for (int i = 1; i < 1000; i++)
	{
		const double an = -i * (i - a);
		b += 2.0;
		d = an * d + b;
		if (std::abs(d) < tiny) d = tiny;
		c = b + an / c;
		if (std::abs(c) < tiny) c = tiny;
		d = 1.0 / d;
		const double delta = d * c;
		h *= delta;
		if (std::abs(delta - 1.0) < 1e-16) break;
	}
	return std::exp(-x + a * std::log(x) - std::lgamma(a)) * h;
}
}  // namespace

double chi2_cdf(double x, int dof)
{
	if (dof < 1) throw std::invalid_argument("chi2: degrees of freedom must be >= 1, got " + std::to_string(dof));
	if (!(x > 0)) return 0.0;
	const double a = 0.5 * dof, h = 0.5 * x;
	return h < a + 1.0 ? gamma_p_series(a, h) : 1.0 - gamma_q_fraction(a, h);
}

double chi2_quantile(double p, int dof)
{
	if (!(p > 0 && p < 1)) throw std::invalid_argument("chi2: probability must be in (0, 1), got " + std::to_string(p));
	if (dof < 1) throw std::invalid_argument("chi2: degrees of freedom must be >= 1, got " + std::to_string(dof));
	double lo = 0.0, hi = dof + 10.0;
	while (chi2_cdf(hi, dof) < p) hi *= 2.0;
	while (hi - lo > 1e-12 * hi)
	{
		const double mid = 0.5 * (lo + hi);
		(chi2_cdf(mid, dof) < p ? lo : hi) = mid;
	}
	return 0.5 * (lo + hi);
}
}  // namespace swba
