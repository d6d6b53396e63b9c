// Tests of BodyVelocityPriorFactor: Jacobians against central differences, and the invariance it
// exists for (a rotation of the world applied to the pose and the velocity leaves the residual).
#include "factor_test_fixtures.h"

#include <swba/factors/body_velocity_prior.h>

using namespace swba;
using namespace swba::factor_test;

TEST(BodyVelocityPrior, JacobiansMatchCentralDifferences)
{
	Rng rng(36);
	for (int k = 0; k < 6; k++)
	{
		const Pose T = rng.pose();
		const Eigen::Vector3d v = rng.vec(-3, 3);
		const BodyVelocityPriorFactor f(rng.vec(-2, 2));
		expect_jacobians_match(f, {T.data(), v.data()}, {se3(), rn(3)}, "BodyVelocityPriorFactor", "random " + std::to_string(k));
	}
	// Nasty: the pose at π, and a zero velocity.
	const Pose T = make_pose(axis_angle(M_PI, rng.unit()), rng.vec(-1, 1));
	const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
	const BodyVelocityPriorFactor f(rng.vec(-1, 1));
	expect_jacobians_match(f, {T.data(), zero.data()}, {se3(), rn(3)}, "BodyVelocityPriorFactor", "pi, zero velocity");
}

TEST(BodyVelocityPrior, ResidualIsInvariantUnderAWorldRotation)
{
	Rng rng(7);
	const Pose T = rng.pose();
	const Eigen::Vector3d v = rng.vec(-3, 3);
	const Eigen::Matrix3d Q = rng.rotation();
	const Pose QT = make_pose(Q * rotation(T), Q * translation(T) + rng.vec(-1, 1));
	const Eigen::Vector3d Qv = Q * v;
	const BodyVelocityPriorFactor f(rng.vec(-2, 2));
	Eigen::Vector3d r, rq;
	const double* x[] = {T.data(), v.data()};
	const double* xq[] = {QT.data(), Qv.data()};
	ASSERT_TRUE(f.evaluate(x, r.data(), nullptr));
	ASSERT_TRUE(f.evaluate(xq, rq.data(), nullptr));
	EXPECT_LT((r - rq).norm(), 1e-12);
	EXPECT_LT((r - (rotation(T).transpose() * v - f.prior())).norm(), 1e-12);
}
