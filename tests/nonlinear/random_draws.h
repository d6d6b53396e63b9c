// Random draws for the scenes of tests/nonlinear.
#pragma once

#include <Eigen/Core>

#include <random>

/** A vector of three standard normal draws, drawn in the order z, y, x. The scenes were first built with
 * the three draws as the arguments of one constructor call, whose evaluation order is the compiler's
 * (gcc: right to left; clang: left to right), so one seed gave two scenes; this fixes the order to the
 * one the tests' bounds were checked on. */
inline Eigen::Vector3d normal3(std::normal_distribution<double>& N, std::mt19937& rng)
{
	Eigen::Vector3d v;
	for (int k = 2; k >= 0; k--) v[k] = N(rng);
	return v;
}
