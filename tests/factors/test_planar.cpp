// Tests of the planar model's pieces (swba/factors/planar.h): the subspace manifold and the factor
// decorator, on the odometry and range-bearing factors the planar estimators use.
#include "factor_test_fixtures.h"

#include <swba/factors/between_pose.h>
#include <swba/factors/planar.h>
#include <swba/factors/range_bearing.h>

#include <mrpt/math/wrap2pi.h>

using namespace swba;
using namespace swba::factor_test;
using mrpt::poses::CPose3D;

namespace
{
/** A random pose on the plane z = 0 (any yaw, including near ±π). */
Pose planar_pose(Rng& rng) { return make_pose(CPose3D(rng.uniform(-5, 5), rng.uniform(-5, 5), 0, rng.uniform(-3.1, 3.1), 0, 0)); }

const Manifold* pp() { return planar_pose_manifold().get(); }
const Manifold* ppt() { return planar_point_manifold().get(); }
}  // namespace

TEST(Planar, PoseUpdateStaysOnThePlaneAndMinusInvertsPlus)
{
	Rng rng(7);
	for (int k = 0; k < 20; k++)
	{
		const Pose x = planar_pose(rng);
		const Eigen::Vector3d d = rng.vec(-1, 1);
		Pose y(12);
		pp()->plus(x.data(), d.data(), y.data());
		const CPose3D p = to_cpose(y);
		EXPECT_NEAR(p.z(), 0.0, 1e-15);
		EXPECT_NEAR(p.pitch(), 0.0, 1e-15);
		EXPECT_NEAR(p.roll(), 0.0, 1e-15);
		// (ρx, ρy, ωz): the yaw moves by δθ, the position by R·(δx, δy).
		EXPECT_NEAR(mrpt::math::wrapToPi(p.yaw() - to_cpose(x).yaw() - d[2]), 0.0, 1e-12);
		Eigen::Vector3d back;
		pp()->minus(y.data(), x.data(), back.data());
		EXPECT_LE((back - d).norm(), 1e-12);
	}
}

TEST(Planar, PointUpdateKeepsItsHeight)
{
	const Eigen::Vector3d p(1.0, 2.0, 0.7), d2(0.25, -0.5, 0.0);
	Eigen::Vector3d q;
	ppt()->plus(p.data(), d2.data(), q.data());
	EXPECT_EQ(q, Eigen::Vector3d(1.25, 1.5, 0.7));
	Eigen::Vector2d back;
	ppt()->minus(q.data(), p.data(), back.data());
	EXPECT_LE((back - d2.head<2>()).norm(), 1e-15);
}

TEST(Planar, SelectionsAreChecked)
{
	auto inner = std::make_shared<BetweenPoseFactor>(CPose3D());
	EXPECT_THROW(SubspaceManifold(euclidean_manifold(3), {0, 3}), std::invalid_argument);
	EXPECT_THROW(SubspaceManifold(euclidean_manifold(3), {1, 0}), std::invalid_argument);
	EXPECT_THROW(SubspaceFactor(inner, {0, 6}, {{}, {}}), std::invalid_argument);
	EXPECT_THROW(SubspaceFactor(inner, {0, 1}, {{}}), std::invalid_argument);
	const SubspaceFactor f(inner, {0, 1, 5}, {planar_pose_coordinates(), {}});
	EXPECT_EQ(f.residual_dim(), 3);
	EXPECT_EQ(f.tangent_dims(), (std::vector<int>{3, 6}));
}

// The planar odometry factor: rows (ρx, ρy, ωz) of the SE(3) between-factor on planar poses. The
// dropped rows (z, roll, pitch) are zero on the plane, and the Jacobians match central differences
// through the planar manifold.
TEST(Planar, OdometryFactorJacobiansAndDroppedRows)
{
	Rng rng(11);
	for (int k = 0; k < 20; k++)
	{
		const Pose Ti = planar_pose(rng), Tj = planar_pose(rng);
		const CPose3D Z(rng.uniform(-1, 1), rng.uniform(-1, 1), 0, rng.uniform(-3, 3), 0, 0);
		auto inner = std::make_shared<BetweenPoseFactor>(Z);
		const SubspaceFactor f(inner, planar_pose_coordinates(), {planar_pose_coordinates(), planar_pose_coordinates()});
		const std::vector<const double*> x{Ti.data(), Tj.data()};
		Eigen::Matrix<double, 6, 1> full;
		ASSERT_TRUE(inner->evaluate(x.data(), full.data(), nullptr));
		EXPECT_LE(full.segment<3>(2).norm(), 1e-12) << "z, roll, pitch rows of a planar between-factor";
		Eigen::Vector3d r;
		ASSERT_TRUE(f.evaluate(x.data(), r.data(), nullptr));
		EXPECT_EQ(r, Eigen::Vector3d(full[0], full[1], full[5]));
		expect_jacobians_match(f, x, {pp(), pp()}, "planar between", "random " + std::to_string(k));
	}
}

// The planar reading: rows (range, yaw) of the range-bearing factor, a planar pose and a point at the
// sensor's height (pitch row zero), with a sensor offset on the robot.
TEST(Planar, RangeYawFactorJacobiansAndDroppedRow)
{
	Rng rng(13);
	const CPose3D sensor(0.3, -0.1, 0.4, 0.5, 0, 0);
	for (int k = 0; k < 20; k++)
	{
		const Pose T = planar_pose(rng);
		const Eigen::Vector3d p(rng.uniform(-8, 8), rng.uniform(-8, 8), sensor.z());
		const RangeBearingMeasurement z{rng.uniform(1, 5), rng.uniform(-3, 3), 0.0};
		auto inner = std::make_shared<RangeBearingXyzFactor>(z, sensor);
		const SubspaceFactor f(inner, {0, 1}, {planar_pose_coordinates(), {0, 1}});
		const std::vector<const double*> x{T.data(), p.data()};
		Eigen::Vector3d full;
		ASSERT_TRUE(inner->evaluate(x.data(), full.data(), nullptr));
		EXPECT_LE(std::abs(full[2]), 1e-12) << "pitch row of a point at the sensor's height";
		Eigen::Vector2d r;
		ASSERT_TRUE(f.evaluate(x.data(), r.data(), nullptr));
		EXPECT_EQ(r, full.head<2>());
		expect_jacobians_match(f, x, {pp(), ppt()}, "planar range-yaw", "random " + std::to_string(k));
	}
}
