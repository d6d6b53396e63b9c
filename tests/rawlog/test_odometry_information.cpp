// Odometry covariance (x y z yaw pitch roll) → information of the SE(3) between-factor in MRPT's
// pseudo-log tangent space.
#include <swba/io/rawlog.h>

#include <mrpt/poses/Lie/SE.h>
#include <mrpt/random/RandomGenerators.h>

#include <Eigen/Dense>
#include <gtest/gtest.h>

namespace
{
Eigen::Matrix<double, 6, 1> pseudo_log(const mrpt::poses::CPose3D& T)
{
	const auto v = mrpt::poses::Lie::SE<3>::log(T);
	Eigen::Matrix<double, 6, 1> r;
	for (int i = 0; i < 6; i++) r[i] = v[i];
	return r;
}

/** Central difference of d ↦ Log(Z⁻¹·Z(ypr + d)). */
Eigen::Matrix<double, 6, 6> numeric_jacobian(const mrpt::poses::CPose3D& Z, double h)
{
	Eigen::Matrix<double, 6, 6> J;
	for (int j = 0; j < 6; j++)
	{
		double p[6], m[6];
		for (int i = 0; i < 6; i++) p[i] = m[i] = Z[i];
		p[j] += h;
		m[j] -= h;
		const mrpt::poses::CPose3D Zp(p[0], p[1], p[2], p[3], p[4], p[5]);
		const mrpt::poses::CPose3D Zm(m[0], m[1], m[2], m[3], m[4], m[5]);
		J.col(j) = (pseudo_log(Zp - Z) - pseudo_log(Zm - Z)) / (2 * h);
	}
	return J;
}
}  // namespace

TEST(OdometryInformation, AnalyticJacobianMatchesCentralDifference)
{
	auto& rng = mrpt::random::getRandomGenerator();
	rng.randomize(1234);
	for (int trial = 0; trial < 50; trial++)
	{
		const mrpt::poses::CPose3D Z(
			rng.drawUniform(-2, 2), rng.drawUniform(-2, 2), rng.drawUniform(-2, 2), rng.drawUniform(-3, 3),
			rng.drawUniform(-1.4, 1.4), rng.drawUniform(-3, 3));
		const auto Ja = swba::io::ypr_to_tangent_jacobian(Z);
		const auto Jn = numeric_jacobian(Z, 1e-6);
		EXPECT_LE((Ja - Jn).norm(), 1e-6 * std::max(1.0, Ja.norm())) << "trial " << trial << "\n" << Ja << "\n\n" << Jn;
	}
}

TEST(OdometryInformation, TangentCovarianceIsJSigmaJt)
{
	mrpt::poses::CPose3DPDFGaussian odo;
	odo.mean = mrpt::poses::CPose3D(0.2, 0.01, -0.03, 0.05, 0.3, -0.4);
	Eigen::Matrix<double, 6, 6> A = Eigen::Matrix<double, 6, 6>::Random();
	const Eigen::Matrix<double, 6, 6> S = 1e-3 * (A * A.transpose()) + 1e-4 * Eigen::Matrix<double, 6, 6>::Identity();
	odo.cov = mrpt::math::CMatrixDouble66(S);
	const auto Jn = numeric_jacobian(odo.mean, 1e-6);
	const Eigen::Matrix<double, 6, 6> expected = Jn * S * Jn.transpose();
	const auto got = swba::io::odometry_tangent_covariance(odo);
	EXPECT_LE((got - expected).norm(), 1e-6 * expected.norm());
	// Well above the floor, the information is the plain inverse.
	const auto info = swba::io::odometry_information(odo);
	EXPECT_LE((info * expected - Eigen::Matrix<double, 6, 6>::Identity()).norm(), 1e-5);
}

TEST(OdometryInformation, FloorMakes2dOdometryFinite)
{
	// 2D odometry lifted to 3D: zero variance in z, pitch, roll.
	mrpt::poses::CPose3DPDFGaussian odo;
	odo.mean = mrpt::poses::CPose3D(0.2, 0.0, 0.0, 0.087, 0.0, 0.0);
	odo.cov.setZero();
	odo.cov(0, 0) = odo.cov(1, 1) = 0.01 * 0.01;
	odo.cov(3, 3) = 0.001 * 0.001;
	swba::io::OdometryInformationOptions opt;
	opt.min_sigma_translation = 1e-3;
	opt.min_sigma_rotation = 2e-3;
	const auto info = swba::io::odometry_information(odo, opt);
	ASSERT_TRUE(info.allFinite());
	Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> es(info);
	EXPECT_GT(es.eigenvalues().minCoeff(), 0.0);
	// The floored directions get exactly 1/σ_min²: z (ρ_z) and ω_x, ω_y (pitch/roll at zero pitch/roll).
	EXPECT_NEAR(info(2, 2), 1.0 / (1e-3 * 1e-3), 1e-3);
	EXPECT_NEAR(info(3, 3), 1.0 / (2e-3 * 2e-3), 1e-3);
	EXPECT_NEAR(info(4, 4), 1.0 / (2e-3 * 2e-3), 1e-3);
	// The yaw variance (1e-6) is below the rotational floor (4e-6): floored to 1/4e-6.
	EXPECT_NEAR(info(5, 5), 1.0 / (2e-3 * 2e-3), 1e-3);
	// x/y variance 1e-4 is above the floor 1e-6: kept, rotated into the body frame (isotropic here).
	EXPECT_NEAR(info(0, 0), 1e4, 1e-6);
	EXPECT_NEAR(info(1, 1), 1e4, 1e-6);
	EXPECT_THROW(swba::io::odometry_information(odo, {0.0, 1e-3}), std::invalid_argument);
}

// The planar odometry factor's information: the inverse of the (ρx, ρy, ωz) block of Σ_tangent, i.e.
// of J Σ_(x,y,yaw) Jᵀ with J = diag(R(yaw)ᵀ, 1), correlations included; nothing from z/pitch/roll.
TEST(OdometryInformation, PlanarInformationIsTheInverseOfThePlanarCovariance)
{
	mrpt::poses::CPose3DPDFGaussian odo;
	const double yaw = 0.7;
	odo.mean = mrpt::poses::CPose3D(0.3, -0.1, 0.0, yaw, 0.0, 0.0);
	odo.cov.setZero();
	Eigen::Matrix3d S;  // (x, y, yaw), correlated
	S << 4e-4, 1e-4, 2e-5, 1e-4, 9e-4, -3e-5, 2e-5, -3e-5, 1e-4;
	const int idx[3] = {0, 1, 3};
	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++) odo.cov(idx[i], idx[j]) = S(i, j);
	Eigen::Matrix3d J = Eigen::Matrix3d::Identity();
	J.topLeftCorner<2, 2>() << std::cos(yaw), std::sin(yaw), -std::sin(yaw), std::cos(yaw);  // R(yaw)ᵀ
	const Eigen::Matrix3d expected_cov = J * S * J.transpose();
	const Eigen::Matrix3d info = swba::io::planar_odometry_information(odo);
	EXPECT_LE((info * expected_cov - Eigen::Matrix3d::Identity()).norm(), 1e-9);
	// Floors: a yaw variance below the rotational floor is raised to it.
	odo.cov.setZero();
	odo.cov(0, 0) = odo.cov(1, 1) = 1e-4;
	const Eigen::Matrix3d floored = swba::io::planar_odometry_information(odo, {1e-3, 2e-3});
	EXPECT_NEAR(floored(2, 2), 1.0 / (2e-3 * 2e-3), 1e-3);
	EXPECT_NEAR(floored(0, 0), 1e4, 1e-6);
	EXPECT_THROW(swba::io::planar_odometry_information(odo, {1e-3, 0.0}), std::invalid_argument);
}
