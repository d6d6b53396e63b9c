/** \file factor_test_fixtures.h
 * Shared helpers for the factor tests: SE(3) values from rotations, random and "nasty" poses
 * (tiny angles, angles near π, exactly π), and a Jacobian check that records the worst error. */
#pragma once

#include <swba/core/factor.h>
#include <swba/core/manifold.h>
#include <swba/core/numeric_diff.h>

#include <gtest/gtest.h>
#include <mrpt/poses/CPose3D.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <string>
#include <vector>

namespace swba::factor_test
{
using Pose = std::vector<double>;  // SE3Manifold storage (12 doubles)

inline Pose make_pose(const Eigen::Matrix3d& R, const Eigen::Vector3d& t)
{
	Pose x(SE3Manifold::kAmbient);
	auto v = se3_view(x.data());
	v.leftCols<3>() = R;
	v.col(3) = t;
	return x;
}

inline Pose make_pose(const mrpt::poses::CPose3D& p)
{
	Pose x(SE3Manifold::kAmbient);
	SE3Manifold::from_pose(p, x.data());
	return x;
}

inline mrpt::poses::CPose3D to_cpose(const Pose& x) { return SE3Manifold::to_pose(x.data()); }

inline Eigen::Matrix3d rotation(const Pose& x) { return se3_view(x.data()).leftCols<3>(); }
inline Eigen::Vector3d translation(const Pose& x) { return se3_view(x.data()).col(3); }

/** Rotation by `angle` about a (normalised) axis. */
inline Eigen::Matrix3d axis_angle(double angle, const Eigen::Vector3d& axis)
{
	return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

/** The SE(3) manifold as a raw pointer, for compare_jacobians. */
inline const Manifold* se3() { return SE3Manifold::instance().get(); }
inline const Manifold* rn(int n) { return euclidean_manifold(n).get(); }

class Rng
{
   public:
	explicit Rng(unsigned seed) : gen_(seed) {}
	double uniform(double a, double b) { return std::uniform_real_distribution<double>(a, b)(gen_); }
	Eigen::Vector3d vec(double a, double b) { return {uniform(a, b), uniform(a, b), uniform(a, b)}; }
	Eigen::Vector3d unit() { return vec(-1, 1).normalized(); }
	/** Uniformly random rotation (random unit quaternion). */
	Eigen::Matrix3d rotation()
	{
		Eigen::Vector4d q(normal(), normal(), normal(), normal());
		q.normalize();
		return Eigen::Quaterniond(q[0], q[1], q[2], q[3]).toRotationMatrix();
	}
	Pose pose(double t_range = 5.0) { return make_pose(rotation(), vec(-t_range, t_range)); }
	double normal() { return std::normal_distribution<double>(0, 1)(gen_); }

   private:
	std::mt19937 gen_;
};

/** Worst relative Jacobian error per factor type, printed when the test binary ends. */
struct WorstErrors
{
	static std::map<std::string, double>& table()
	{
		static std::map<std::string, double> t;
		return t;
	}
	static void record(const std::string& name, double err)
	{
		auto& w = table()[name];
		w = std::max(w, err);
	}
};

/** Analytic vs central-difference Jacobians (relative 1e-6, the project's bound); `h` is the
 * central-difference step in the tangent space. */
inline void expect_jacobians_match(const Factor& factor, const std::vector<const double*>& x,
								   const std::vector<const Manifold*>& manifolds, const std::string& name,
								   const std::string& config, double h = 1e-6)
{
	const JacobianComparison cmp = compare_jacobians(factor, x, manifolds, h);
	const double err = cmp.max_relative_error();
	WorstErrors::record(name, err);
	EXPECT_LE(err, 1e-6) << name << " at configuration '" << config << "'";
	if (err > 1e-6)
		for (size_t i = 0; i < cmp.analytic.size(); i++)
			ADD_FAILURE() << "variable " << i << "\nanalytic:\n"
						  << cmp.analytic[i] << "\nnumeric:\n"
						  << cmp.numeric[i];
}
}  // namespace swba::factor_test
