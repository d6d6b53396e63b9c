// SnavelyReprojectionFactor: residual by hand, analytic Jacobians vs central differences
// (random cameras with k1, k2 ≠ 0, tiny and exactly-zero rotations, both sides of the series switch).
#include <gtest/gtest.h>
#include <swba/core/manifold.h>
#include <swba/core/numeric_diff.h>
#include <swba/factors/snavely_reprojection.h>

#include <Eigen/Geometry>
#include <array>
#include <random>

namespace
{
using swba::SnavelyReprojectionFactor;

struct Fixture
{
	std::array<double, 9> camera;
	std::array<double, 3> point;
};

// A random camera whose rotation vector has norm `rotation_norm`, and a point in front of it
// (camera-frame depth 2..10 along −z) or behind it (`behind`).
Fixture random_fixture(std::mt19937& rng, double rotation_norm, bool behind = false)
{
	std::uniform_real_distribution<double> u(-1.0, 1.0);
	Fixture fx;
	Eigen::Vector3d axis(u(rng), u(rng), u(rng));
	axis.normalize();
	const Eigen::Vector3d omega = rotation_norm * axis;
	const Eigen::Vector3d t(u(rng), u(rng), u(rng));
	fx.camera = {omega.x(), omega.y(), omega.z(), t.x(), t.y(), t.z(), 500.0 + 100.0 * u(rng), 0.3 * u(rng),
				 0.1 * u(rng)};
	const double depth = 6.0 + 4.0 * u(rng);
	const Eigen::Vector3d P(0.5 * depth * u(rng), 0.5 * depth * u(rng), behind ? depth : -depth);
	const Eigen::Matrix3d R =
		rotation_norm > 0 ? Eigen::AngleAxisd(rotation_norm, axis).toRotationMatrix() : Eigen::Matrix3d::Identity();
	const Eigen::Vector3d X = R.transpose() * (P - t);
	fx.point = {X.x(), X.y(), X.z()};
	return fx;
}

double max_jacobian_error(const Fixture& fx, double h = 1e-6)
{
	const SnavelyReprojectionFactor factor(12.5, -30.0);
	const auto cam_m = swba::euclidean_manifold(9);
	const auto pt_m = swba::euclidean_manifold(3);
	const auto cmp = swba::compare_jacobians(factor, {fx.camera.data(), fx.point.data()}, {cam_m.get(), pt_m.get()}, h);
	return cmp.max_relative_error();
}
}  // namespace

TEST(SnavelyFactor, ResidualMatchesTheModelByHand)
{
	// ω = 0, t = (0.5, −1, 2): P = X + t = (1.5, 1, −2) → p = (0.75, 0.5), ‖p‖² = 0.8125.
	const double cam[9] = {0, 0, 0, 0.5, -1.0, 2.0, 400.0, -0.2, 0.05};
	const double X[3] = {1.0, 2.0, -4.0};
	const double n = 0.8125;
	const double r = 1.0 - 0.2 * n + 0.05 * n * n;
	const SnavelyReprojectionFactor factor(10.0, 20.0);
	const double* x[2] = {cam, X};
	double res[2];
	ASSERT_TRUE(factor.evaluate(x, res, nullptr));
	EXPECT_NEAR(res[0], 400.0 * r * 0.75 - 10.0, 1e-12);
	EXPECT_NEAR(res[1], 400.0 * r * 0.5 - 20.0, 1e-12);
}

TEST(SnavelyFactor, RotationMatchesEigenAngleAxis)
{
	std::mt19937 rng(7);
	std::uniform_real_distribution<double> u(-1.0, 1.0);
	for (double norm : {0.0, 1e-12, 1e-7, 1e-4, 0.0999, 0.1, 0.1001, 0.5, 2.0, 3.1})
		for (int k = 0; k < 5; k++)
		{
			Eigen::Vector3d axis(u(rng), u(rng), u(rng));
			axis.normalize();
			const Eigen::Vector3d w = norm * axis;
			const Eigen::Vector3d X(u(rng) * 3, u(rng) * 3, u(rng) * 3);
			const Eigen::Vector3d expected = Eigen::AngleAxisd(norm, axis) * X;
			const Eigen::Vector3d got = swba::angle_axis_rotate_point(w.data(), X);
			EXPECT_LT((got - expected).norm(), 1e-14 * (1 + X.norm())) << "norm " << norm;
		}
}

TEST(SnavelyFactor, CameraCentreProjectsToTheOrigin)
{
	std::mt19937 rng(3);
	for (int k = 0; k < 10; k++)
	{
		const Fixture fx = random_fixture(rng, 0.3 * (k + 1));
		const Eigen::Vector3d c = swba::snavely_camera_centre(fx.camera.data());
		const Eigen::Vector3d P = swba::angle_axis_rotate_point(fx.camera.data(), c) +
								  Eigen::Vector3d(fx.camera[3], fx.camera[4], fx.camera[5]);
		EXPECT_LT(P.norm(), 1e-12);
	}
}

TEST(SnavelyFactor, JacobiansMatchNumericForRandomCameras)
{
	std::mt19937 rng(42);
	std::uniform_real_distribution<double> angle(0.2, 3.0);
	for (int k = 0; k < 30; k++)
	{
		const Fixture fx = random_fixture(rng, angle(rng));
		ASSERT_NE(fx.camera[7], 0.0);
		ASSERT_NE(fx.camera[8], 0.0);
		EXPECT_LE(max_jacobian_error(fx), 1e-6) << "fixture " << k;
	}
}

TEST(SnavelyFactor, JacobiansMatchNumericNearZeroRotation)
{
	std::mt19937 rng(11);
	// 0 exactly, tiny, and both sides of the Taylor-series switch at ‖ω‖ = 0.1.
	for (double norm : {0.0, 1e-12, 1e-8, 1e-5, 1e-3, 0.0999, 0.1001})
		for (int k = 0; k < 4; k++)
		{
			const Fixture fx = random_fixture(rng, norm);
			EXPECT_LE(max_jacobian_error(fx), 1e-6) << "norm " << norm;
		}
}

TEST(SnavelyFactor, PointBehindCameraIsEvaluatedAndZeroDepthIsRejected)
{
	std::mt19937 rng(5);
	const Fixture behind = random_fixture(rng, 0.4, /*behind=*/true);
	const SnavelyReprojectionFactor factor(0.0, 0.0);
	const double* x[2] = {behind.camera.data(), behind.point.data()};
	double res[2];
	EXPECT_TRUE(factor.evaluate(x, res, nullptr));
	EXPECT_LE(max_jacobian_error(behind), 1e-6);

	// A point in the camera's z = 0 plane: the projection is undefined.
	const double cam[9] = {0, 0, 0, 0, 0, 0, 500, 0, 0};
	const double X[3] = {1.0, 1.0, 0.0};
	const double* x0[2] = {cam, X};
	EXPECT_FALSE(factor.evaluate(x0, res, nullptr));
}

TEST(SnavelyFactor, PartialJacobianRequestsAgreeWithFullOnes)
{
	std::mt19937 rng(9);
	const Fixture fx = random_fixture(rng, 0.7);
	const SnavelyReprojectionFactor factor(1.0, 2.0);
	const double* x[2] = {fx.camera.data(), fx.point.data()};
	double r_full[2], r_cam[2], r_pt[2], Jc_full[18], Jp_full[6], Jc[18], Jp[6];
	double* both[2] = {Jc_full, Jp_full};
	double* cam_only[2] = {Jc, nullptr};
	double* pt_only[2] = {nullptr, Jp};
	ASSERT_TRUE(factor.evaluate(x, r_full, both));
	ASSERT_TRUE(factor.evaluate(x, r_cam, cam_only));
	ASSERT_TRUE(factor.evaluate(x, r_pt, pt_only));
	for (int i = 0; i < 18; i++) EXPECT_EQ(Jc[i], Jc_full[i]);
	for (int i = 0; i < 6; i++) EXPECT_EQ(Jp[i], Jp_full[i]);
	EXPECT_EQ(r_cam[0], r_full[0]);
	EXPECT_EQ(r_pt[1], r_full[1]);
}
