// Internal to modules/problems: angle wrapping shared by the 2D pose-graph residuals and initialisation.
#pragma once

#include <cmath>

namespace swba::problems::detail
{
/** a wrapped into (−π, π] by std::remainder. Not mrpt::math::wrapToPi, which computes
 * wrapTo2Pi(a + π) − π and so loses the low bits of small angles (residuals near convergence). */
inline double wrap_pm_pi(double a)
{
	a = std::remainder(a, 2.0 * M_PI);
	if (a <= -M_PI) a += 2.0 * M_PI;
	return a;
}
}  // namespace swba::problems::detail
