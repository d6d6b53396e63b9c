// Tests of ImuPreintegrationFactor and EuclideanPriorFactor: every Jacobian block against central
// differences at random states and biases, and a zero residual at states that the same readings produce.
#include "factor_test_fixtures.h"

#include <swba/core/lie.h>
#include <swba/factors/imu_factor.h>

using namespace swba;
using namespace swba::factor_test;

namespace
{
std::shared_ptr<ImuPreintegration> random_preintegration(Rng& rng, const Vector6d& bias_lin, int n = 61)
{
	auto pim = std::make_shared<ImuPreintegration>(ImuNoise{}, bias_lin);
	const Eigen::Vector3d w0 = rng.vec(-1.5, 1.5), a0 = rng.vec(-3, 3) + Eigen::Vector3d(0, 0, 9.8);
	for (int k = 0; k < n; k++)
	{
		const double t = 0.005 * k;
		pim->add_sample({t, a0 + Eigen::Vector3d(std::sin(5 * t), 0.3, -std::cos(2 * t)), w0 + Eigen::Vector3d(0.2 * t, 0, -0.4 * t)});
	}
	return pim;
}

Vector6d random_bias(Rng& rng, double sa, double sg)
{
	Vector6d b;
	b << rng.vec(-sa, sa), rng.vec(-sg, sg);
	return b;
}
}  // namespace

TEST(ImuPreintegrationFactor, JacobiansMatchNumericAtRandomStates)
{
	for (unsigned seed = 1; seed <= 8; seed++)
	{
		Rng rng(seed);
		const Vector6d bias_lin = random_bias(rng, 0.2, 0.05);
		const ImuPreintegrationFactor f(random_preintegration(rng, bias_lin));
		const Pose Ti = rng.pose(), Tj = rng.pose();
		const Eigen::Vector3d vi = rng.vec(-3, 3), vj = rng.vec(-3, 3);
		// b_i away from the linearisation bias, so that the correction's Jacobian is not the identity.
		const Vector6d bi = bias_lin + random_bias(rng, 0.1, 0.05), bj = random_bias(rng, 0.2, 0.05);
		expect_jacobians_match(f, {Ti.data(), vi.data(), bi.data(), Tj.data(), vj.data(), bj.data()},
							   {se3(), rn(3), rn(6), se3(), rn(3), rn(6)}, "ImuPreintegrationFactor",
							   "random " + std::to_string(seed));
	}
}

TEST(ImuPreintegrationFactor, JacobiansMatchNumericNearTheSolution)
{
	// States consistent with the readings (residual ≈ 0, small angles in r_R) and b_i = b̄.
	Rng rng(42);
	const Vector6d b = random_bias(rng, 0.1, 0.01);
	auto pim = random_preintegration(rng, b);
	const ImuPreintegrationFactor f(pim);
	NavState xi;
	xi.R = axis_angle(1e-5, rng.unit());
	xi.v = rng.vec(-1, 1);
	const NavState xj = pim->predict(xi, b);
	const Pose Ti = make_pose(xi.R, xi.p), Tj = make_pose(xj.R, xj.p);
	expect_jacobians_match(f, {Ti.data(), xi.v.data(), b.data(), Tj.data(), xj.v.data(), b.data()},
						   {se3(), rn(3), rn(6), se3(), rn(3), rn(6)}, "ImuPreintegrationFactor", "at the solution");
	Eigen::Matrix<double, 15, 1> r;
	const double* x[] = {Ti.data(), xi.v.data(), b.data(), Tj.data(), xj.v.data(), b.data()};
	ASSERT_TRUE(f.evaluate(x, r.data(), nullptr));
	EXPECT_LT(r.norm(), 1e-12);
}

TEST(ImuPreintegrationFactor, ResidualIsZeroAtMidpointDeadReckoning)
{
	// Navigation with the world gravity and the factor's gravity term must agree: a sign error in
	// either gives a residual of order g·Δt.
	Rng rng(9);
	const Vector6d b = random_bias(rng, 0.1, 0.01);
	auto pim = random_preintegration(rng, b);
	NavState x0;
	x0.R = rng.rotation();
	x0.p = rng.vec(-3, 3);
	x0.v = rng.vec(-1, 1);
	NavState x = x0;
	const auto& s = pim->samples();
	for (size_t k = 1; k < s.size(); k++) x = imu_midpoint_step(x, s[k - 1], s[k], b, pim->noise().gravity);
	const ImuPreintegrationFactor f(pim);
	const Pose Ti = make_pose(x0.R, x0.p), Tj = make_pose(x.R, x.p);
	const double* xs[] = {Ti.data(), x0.v.data(), b.data(), Tj.data(), x.v.data(), b.data()};
	Eigen::Matrix<double, 15, 1> r;
	ASSERT_TRUE(f.evaluate(xs, r.data(), nullptr));
	EXPECT_LT(r.norm(), 1e-10);
}

TEST(ImuPreintegrationFactor, WhiteningIsInverseCovariance)
{
	Rng rng(4);
	auto pim = random_preintegration(rng, Vector6d::Zero());
	const ImuPreintegrationFactor f(pim);
	const Eigen::MatrixXd W = f.sqrt_information();
	const Eigen::MatrixXd should_be_identity = W * pim->covariance() * W.transpose();
	EXPECT_LT((should_be_identity - Eigen::MatrixXd::Identity(15, 15)).cwiseAbs().maxCoeff(), 1e-6);
}

TEST(ImuPreintegrationFactor, RejectsEmptyPreintegration)
{
	auto pim = std::make_shared<ImuPreintegration>(ImuNoise{}, Vector6d::Zero());
	pim->add_sample({0.0, Eigen::Vector3d(0, 0, 9.81), Eigen::Vector3d::Zero()});
	EXPECT_THROW(ImuPreintegrationFactor f(pim), std::invalid_argument);
}

TEST(EuclideanPriorFactor, ResidualAndJacobian)
{
	Eigen::VectorXd mean(6);
	mean << 1, 2, 3, 4, 5, 6;
	const EuclideanPriorFactor f(mean);
	Eigen::VectorXd x(6);
	x << 1.5, 2, 3, 4, 5, 7;
	expect_jacobians_match(f, {x.data()}, {rn(6)}, "EuclideanPriorFactor", "offset");
	Eigen::VectorXd r(6);
	const double* xs[] = {x.data()};
	ASSERT_TRUE(f.evaluate(xs, r.data(), nullptr));
	EXPECT_DOUBLE_EQ(r[0], 0.5);
	EXPECT_DOUBLE_EQ(r[5], 1.0);
}
