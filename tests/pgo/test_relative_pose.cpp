// Relative-pose factors of the g2o reference model: Jacobians vs central differences, residual
// definitions, and consistency with the independent cost evaluator of swba::io.
#include <swba/core/manifold.h>
#include <swba/core/numeric_diff.h>
#include <swba/factors/relative_pose.h>
#include <swba/io/g2o.h>
#include <swba/problems/pose_graph.h>

#include <gtest/gtest.h>

#include <random>

namespace
{
using swba::SE3Manifold;

Eigen::Quaterniond random_quaternion(std::mt19937& rng, double max_angle)
{
	std::uniform_real_distribution<double> u(-1.0, 1.0);
	Eigen::Vector3d axis(u(rng), u(rng), u(rng));
	axis.normalize();
	const double angle = max_angle * std::abs(u(rng));
	return Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis));
}

std::vector<double> se3_value(const Eigen::Quaterniond& q, const Eigen::Vector3d& t)
{
	std::vector<double> x(SE3Manifold::kAmbient);
	auto T = swba::se3_view(x.data());
	T.leftCols<3>() = q.toRotationMatrix();
	T.col(3) = t;
	return x;
}

TEST(RelativePoseFactor, JacobiansMatchNumericAtRandomPoses)
{
	std::mt19937 rng(42);
	std::uniform_real_distribution<double> u(-3.0, 3.0);
	const SE3Manifold* se3 = SE3Manifold::instance().get();
	for (int trial = 0; trial < 50; trial++)
	{
		// Rotation errors up to ≈ 2.5 rad (away from π, where the w ≥ 0 sign choice switches).
		const auto qa = random_quaternion(rng, M_PI), qab = random_quaternion(rng, M_PI);
		const Eigen::Quaterniond qb = qa * qab * random_quaternion(rng, 2.5);
		const Eigen::Vector3d ta(u(rng), u(rng), u(rng)), tb(u(rng), u(rng), u(rng)), tab(u(rng), u(rng), u(rng));
		const auto xa = se3_value(qa, ta), xb = se3_value(qb, tb);
		for (auto conv : {swba::RotationError::G2o, swba::RotationError::CeresExample})
		{
			const swba::RelativePoseFactor f(qab, tab, conv);
			const auto cmp = swba::compare_jacobians(f, {xa.data(), xb.data()}, {se3, se3});
			EXPECT_LE(cmp.max_relative_error(), 1e-6) << "trial " << trial << " convention " << static_cast<int>(conv);
		}
	}
}

TEST(RelativePoseFactor, ConventionsDifferByTheMeasuredRotation)
{
	// vec q(R_ab·R_bᵀ·R_a) = −R_ab · vec q(R_abᵀ·R_aᵀ·R_b): same norm, rotated error vector.
	std::mt19937 rng(9);
	const auto qa = random_quaternion(rng, M_PI), qab = random_quaternion(rng, M_PI);
	const Eigen::Quaterniond qb = qa * qab * random_quaternion(rng, 0.5);
	const auto xa = se3_value(qa, Eigen::Vector3d(1, 2, 3)), xb = se3_value(qb, Eigen::Vector3d(-1, 0, 2));
	const double* x[2] = {xa.data(), xb.data()};
	double rg[6], rc[6];
	ASSERT_TRUE(swba::RelativePoseFactor(qab, Eigen::Vector3d(0.5, 0, 0), swba::RotationError::G2o).evaluate(x, rg, nullptr));
	ASSERT_TRUE(
		swba::RelativePoseFactor(qab, Eigen::Vector3d(0.5, 0, 0), swba::RotationError::CeresExample).evaluate(x, rc, nullptr));
	const Eigen::Vector3d expected = -(qab * Eigen::Vector3d(rg[3], rg[4], rg[5]));
	for (int i = 0; i < 3; i++)
	{
		EXPECT_EQ(rg[i], rc[i]);  // same translation residual
		EXPECT_NEAR(rc[3 + i], expected[i], 1e-14);
	}
	EXPECT_GT(Eigen::Vector3d(rg[3], rg[4], rg[5]).norm(), 0.05);
	EXPECT_GT((Eigen::Vector3d(rg[3], rg[4], rg[5]) - Eigen::Vector3d(rc[3], rc[4], rc[5])).norm(), 0.01);
}

TEST(RelativePoseFactor, JacobiansMatchNumericNearTheSolution)
{
	const SE3Manifold* se3 = SE3Manifold::instance().get();
	const Eigen::Quaterniond qa(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()));
	const Eigen::Quaterniond qab(Eigen::AngleAxisd(-1.1, Eigen::Vector3d(0, 1, -1).normalized()));
	const Eigen::Vector3d ta(1, -2, 0.5), tab(0.3, 0.1, -0.2);
	// Pose b consistent with the measurement up to a 1e-5 rad rotation error.
	const Eigen::Quaterniond qb = qa * qab * Eigen::Quaterniond(Eigen::AngleAxisd(1e-5, Eigen::Vector3d::UnitX()));
	const Eigen::Vector3d tb = ta + qa * tab;
	const auto xa = se3_value(qa, ta), xb = se3_value(qb, tb);
	for (auto conv : {swba::RotationError::G2o, swba::RotationError::CeresExample})
	{
		const swba::RelativePoseFactor f(qab, tab, conv);
		const auto cmp = swba::compare_jacobians(f, {xa.data(), xb.data()}, {se3, se3});
		EXPECT_LE(cmp.max_relative_error(), 1e-6);
	}
}

TEST(RelativePoseFactor, ResidualIsZeroForAConsistentMeasurementAndMatchesRotationVector)
{
	const Eigen::Quaterniond qa(Eigen::AngleAxisd(0.4, Eigen::Vector3d(0, 0, 1)));
	const Eigen::Quaterniond qab(Eigen::AngleAxisd(0.9, Eigen::Vector3d(1, 1, 0).normalized()));
	const Eigen::Vector3d ta(1, 2, 3), tab(-1, 0.5, 2);
	const swba::RelativePoseFactor f(qab, tab);
	double r[6];
	{
		const auto xa = se3_value(qa, ta), xb = se3_value(qa * qab, ta + qa * tab);
		const double* x[2] = {xa.data(), xb.data()};
		ASSERT_TRUE(f.evaluate(x, r, nullptr));
		for (double v : r) EXPECT_NEAR(v, 0.0, 1e-14);
	}
	// A small extra rotation ω of b (right-multiplied) appears as 2·vec(q) ≈ ω in the residual, so
	// the (qx, qy, qz) information block applies to a rotation-vector error.
	const Eigen::Vector3d w(2e-3, -1e-3, 3e-3);
	const Eigen::Quaterniond qb = qa * qab * Eigen::Quaterniond(Eigen::AngleAxisd(w.norm(), w.normalized()));
	const auto xa = se3_value(qa, ta), xb = se3_value(qb, ta + qa * tab);
	const double* x[2] = {xa.data(), xb.data()};
	ASSERT_TRUE(f.evaluate(x, r, nullptr));
	for (int i = 0; i < 3; i++)
	{
		EXPECT_NEAR(r[i], 0.0, 1e-14);
		EXPECT_NEAR(r[3 + i], w[i], 1e-8);  // 2 sin(θ/2) u − θ u = O(θ³)
	}
}

TEST(PosePriorQuatFactor, JacobiansMatchNumeric)
{
	std::mt19937 rng(7);
	std::uniform_real_distribution<double> u(-2.0, 2.0);
	const SE3Manifold* se3 = SE3Manifold::instance().get();
	for (int trial = 0; trial < 20; trial++)
	{
		const auto q0 = random_quaternion(rng, M_PI);
		const Eigen::Quaterniond q = q0 * random_quaternion(rng, 2.5);
		const auto x = se3_value(q, Eigen::Vector3d(u(rng), u(rng), u(rng)));
		const swba::PosePriorQuatFactor f(q0, Eigen::Vector3d(u(rng), u(rng), u(rng)));
		EXPECT_LE(swba::compare_jacobians(f, {x.data()}, {se3}).max_relative_error(), 1e-6);
	}
}

TEST(RelativePose2dFactor, JacobiansMatchNumericAndAngleWraps)
{
	std::mt19937 rng(3);
	std::uniform_real_distribution<double> u(-3.0, 3.0);
	const auto r3 = swba::euclidean_manifold(3);
	for (int trial = 0; trial < 30; trial++)
	{
		const double a[3] = {u(rng), u(rng), u(rng)}, b[3] = {u(rng), u(rng), u(rng)};
		const swba::RelativePose2dFactor f(u(rng), u(rng), 0.5 * u(rng));
		double r[3];
		const double* x[2] = {a, b};
		ASSERT_TRUE(f.evaluate(x, r, nullptr));
		EXPECT_LE(std::abs(r[2]), M_PI);
		// Skip the few draws whose angle error sits within the numeric step of the ±π cut.
		if (M_PI - std::abs(r[2]) < 1e-4) continue;
		EXPECT_LE(swba::compare_jacobians(f, {a, b}, {r3.get(), r3.get()}).max_relative_error(), 1e-6);
	}
	// θ_b − θ_a − θ_ab = (−π + 0.05) − (π − 0.05) = −2π + 0.1 wraps to 0.1.
	const swba::RelativePose2dFactor f(0, 0, 0.0);
	const double a[3] = {0, 0, M_PI - 0.05}, b[3] = {0, 0, -M_PI + 0.05};
	const double* x[2] = {a, b};
	double r[3];
	ASSERT_TRUE(f.evaluate(x, r, nullptr));
	EXPECT_NEAR(r[2], 0.1, 1e-12);
}

TEST(PosePrior2dFactor, JacobiansMatchNumeric)
{
	const auto r3 = swba::euclidean_manifold(3);
	const double x[3] = {1.5, -0.3, 2.0};
	const swba::PosePrior2dFactor f(0.2, 0.4, -0.7);
	EXPECT_LE(swba::compare_jacobians(f, {x}, {r3.get()}).max_relative_error(), 1e-6);
}

TEST(PoseGraphProblem, ProblemCostEqualsIndependentReferenceCost)
{
	// Problem::cost goes through RelativePoseFactor (rotation matrices, whitening by Lᵀ);
	// pose_graph_cost evaluates ½ rᵀΛr with quaternion algebra: they must agree.
	for (const char* name : {"smallGrid3D.g2o", "sphere2500.g2o", "intel.g2o"})
	{
		const auto g = swba::io::read_g2o(std::string(SWBA_DATA_DIR) + "/posegraph/" + name);
		for (auto conv : {swba::RotationError::G2o, swba::RotationError::CeresExample})
		{
			swba::problems::PoseGraphProblemOptions po;
			po.rotation_error = conv;
			const auto pp = swba::problems::build_pose_graph_problem(g, po);
			const double ref = swba::problems::pose_graph_cost(g, conv);
			EXPECT_GT(ref, 0.0) << name;
			EXPECT_NEAR(pp.problem.cost(), ref, 1e-10 * ref) << name << " " << static_cast<int>(conv);
		}
	}
	// Initial costs of the two 3D conventions as Ceres reports them for sphere2500 (bench/pgo).
	const auto g = swba::io::read_g2o(std::string(SWBA_DATA_DIR) + "/posegraph/sphere2500.g2o");
	EXPECT_NEAR(swba::problems::pose_graph_cost(g, swba::RotationError::G2o), 1292302.995442, 1e-6);
	EXPECT_NEAR(swba::problems::pose_graph_cost(g, swba::RotationError::CeresExample), 1292384.216700, 1e-6);
}
}  // namespace
