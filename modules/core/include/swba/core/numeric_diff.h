/** \file numeric_diff.h
 * Central-difference Jacobians through the manifolds' retraction: the reference every analytic
 * Jacobian is tested against. */
#pragma once

#include <swba/core/factor.h>
#include <swba/core/manifold.h>

#include <Eigen/Core>
#include <vector>

namespace swba
{
using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/** Analytic and numeric (central difference, step h in the tangent space) unwhitened Jacobians of
 * `factor` at values `x` on `manifolds`. */
struct JacobianComparison
{
	std::vector<RowMajorMatrix> analytic, numeric;
	/** max_i ‖A_i − N_i‖_max / max(1, ‖N_i‖_max). */
	double max_relative_error() const;
};

JacobianComparison compare_jacobians(const Factor& factor, const std::vector<const double*>& x,
									 const std::vector<const Manifold*>& manifolds, double h = 1e-6);
}  // namespace swba
