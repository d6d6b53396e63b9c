/** \file chi2.h
 * The χ² distribution's CDF and quantile, for gates and robust-loss scales on whitened residuals:
 * a k-dimensional residual whitened by its true covariance has ‖r‖² ~ χ²_k. (MRPT's chi2CDF / chi2inv
 * are approximations: chi2inv(0.999, 3) = 16.55 instead of 16.27.) */
#pragma once

namespace swba
{
/** P(χ²_dof ≤ x), the regularised lower incomplete gamma P(dof/2, x/2); 0 for x ≤ 0. Relative accuracy
 * ~1e-14 (series below a+1, Lentz's continued fraction above). Throws std::invalid_argument if dof < 1. */
double chi2_cdf(double x, int dof);
/** The p-quantile: x with chi2_cdf(x, dof) = p (bisection to 1e-12 relative), e.g. chi2_quantile(0.999, 3)
 * = 16.266. Throws std::invalid_argument unless 0 < p < 1 and dof ≥ 1. */
double chi2_quantile(double p, int dof);
}  // namespace swba
