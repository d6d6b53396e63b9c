/** \file chi2.h
 * The χ² distribution's CDF and quantile, for gates and robust-loss scales on whitened residuals:
 * a k-dimensional residual whitened by its true covariance has ‖r‖² ~ χ²_k. Computed by Boost.Math
 * (MRPT's chi2CDF / chi2inv are approximations: chi2inv(0.999, 3) = 16.55 instead of 16.27); this
 * header keeps Boost out of core's public interface. */
#pragma once

namespace swba
{
/** P(χ²_dof ≤ x); 0 for x ≤ 0. Throws std::invalid_argument if dof < 1 or x is NaN. */
double chi2_cdf(double x, int dof);
/** The p-quantile: x with chi2_cdf(x, dof) = p, e.g. chi2_quantile(0.999, 3) = 16.266. Throws
 * std::invalid_argument unless 0 < p < 1 and dof ≥ 1. */
double chi2_quantile(double p, int dof);
}  // namespace swba
