// Tests of MonocularInverseDepthFactor (seed 000's mono BA residual on the normalised image plane).
#include "factor_test_fixtures.h"

#include <swba/factors/monocular_inverse_depth.h>

using namespace swba;
using namespace swba::factor_test;
using mrpt::poses::CPose3D;

namespace
{
/** Host and target camera poses (camera-to-world) and a point with depth 1/λ in the host. */
struct MonoCase
{
	std::string name;
	Pose Th, Tt;
	Eigen::Vector2d bearing;  // (u_h, v_h)
	double lambda;
};

/** p_t = T_t⁻¹·T_h·p_h through MRPT's pose algebra (an independent path to the prediction). */
Eigen::Vector3d point_in_target(const MonoCase& c)
{
	const Eigen::Vector3d ph = Eigen::Vector3d(c.bearing.x(), c.bearing.y(), 1.0) / c.lambda;
	const auto pw = to_cpose(c.Th).composePoint(mrpt::math::TPoint3D(ph.x(), ph.y(), ph.z()));
	const auto pt = to_cpose(c.Tt).inverseComposePoint(pw);
	return {pt.x, pt.y, pt.z};
}

Eigen::Vector2d project(const Eigen::Vector3d& p) { return p.head<2>() / p.z(); }

std::vector<MonoCase> mono_cases()
{
	Rng rng(1234);
	std::vector<MonoCase> c;
	auto add = [&](const std::string& name, const Pose& Th, const Eigen::Matrix3d& dR, const Eigen::Vector3d& dt,
				   const Eigen::Vector2d& b, double lambda) {
		// Target = host ⊕ (dR, dt): a second camera near the first, looking roughly the same way.
		const Pose Tt = make_pose(rotation(Th) * dR, translation(Th) + rotation(Th) * dt);
		c.push_back({name, Th, Tt, b, lambda});
	};
	for (int k = 0; k < 6; k++)
		add("random " + std::to_string(k), rng.pose(), axis_angle(rng.uniform(0, 0.3), rng.unit()), rng.vec(-1, 1),
			Eigen::Vector2d(rng.uniform(-0.4, 0.4), rng.uniform(-0.4, 0.4)), rng.uniform(1.0 / 8, 1.0 / 2));
	add("small angles", make_pose(axis_angle(1e-5, rng.unit()), rng.vec(-1, 1)), axis_angle(1e-5, rng.unit()),
		Eigen::Vector3d(0.3, 1e-5, -1e-5), Eigen::Vector2d(1e-5, -1e-5), 0.2);
	add("host at pi, target rolled by pi", make_pose(axis_angle(M_PI, rng.unit()), rng.vec(-3, 3)),
		axis_angle(M_PI, Eigen::Vector3d::UnitZ()), Eigen::Vector3d(0.5, -0.2, 0.1), Eigen::Vector2d(0.1, 0.2), 0.25);
	add("target rolled by pi-1e-9", rng.pose(), axis_angle(M_PI - 1e-9, Eigen::Vector3d(0.01, -0.02, 1.0)),
		Eigen::Vector3d(-0.4, 0.3, 0.2), Eigen::Vector2d(-0.3, 0.05), 0.3);
	add("far point (lambda = 1e-3)", rng.pose(), axis_angle(0.2, rng.unit()), Eigen::Vector3d(1.0, 0.0, 0.2),
		Eigen::Vector2d(0.2, -0.1), 1e-3);
	add("near point (lambda = 20)", rng.pose(), axis_angle(0.01, rng.unit()), Eigen::Vector3d(0.005, 0.002, 0.0),
		Eigen::Vector2d(0.1, 0.1), 20.0);
	add("seed 000 arc", make_pose(Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero()),
		axis_angle(-0.3, Eigen::Vector3d::UnitY()), Eigen::Vector3d(1.5, 0.0, 0.3), Eigen::Vector2d(0.05, -0.02), 0.2);
	for (const auto& m : c) EXPECT_GT(point_in_target(m).z(), 0.0) << m.name;  // fixtures are in front
	return c;
}

Eigen::Vector2d eval2(const Factor& f, const MonoCase& c)
{
	Eigen::Vector2d r;
	const double* x[3] = {c.Th.data(), c.Tt.data(), &c.lambda};
	EXPECT_TRUE(f.evaluate(x, r.data(), nullptr)) << c.name;
	return r;
}
}  // namespace

TEST(MonocularInverseDepth, ZeroResidualAtTruth)
{
	for (const auto& c : mono_cases())
	{
		MonocularInverseDepthFactor f(c.bearing, project(point_in_target(c)));
		EXPECT_LE(eval2(f, c).cwiseAbs().maxCoeff(), 1e-12) << c.name;
	}
}

TEST(MonocularInverseDepth, ResidualIsProjectionOfTinvThPh)
{
	Rng rng(9);
	for (const auto& c : mono_cases())
	{
		const Eigen::Vector2d obs(rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5));
		MonocularInverseDepthFactor f(c.bearing, obs);
		EXPECT_LE((eval2(f, c) - (project(point_in_target(c)) - obs)).cwiseAbs().maxCoeff(), 1e-11) << c.name;
	}
}

TEST(MonocularInverseDepth, JacobiansMatchNumeric)
{
	Rng rng(10);
	const auto cases = mono_cases();
	ASSERT_GE(cases.size(), 5u);
	for (const auto& c : cases)
	{
		const Eigen::Vector2d obs = project(point_in_target(c)) + 1e-3 * Eigen::Vector2d(rng.normal(), rng.normal());
		MonocularInverseDepthFactor f(c.bearing, obs);
		expect_jacobians_match(f, {c.Th.data(), c.Tt.data(), &c.lambda}, {se3(), se3(), rn(1)},
							   "MonocularInverseDepthFactor", c.name);
	}
}

TEST(MonocularInverseDepth, UndefinedBehindTheTargetOrForNonPositiveInverseDepth)
{
	const Pose Th = make_pose(Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero());
	// Target 10 m ahead of the host, looking the same way: a point 5 m ahead of the host is behind it.
	const Pose Tt = make_pose(Eigen::Matrix3d::Identity(), Eigen::Vector3d(0, 0, 10));
	MonocularInverseDepthFactor f(Eigen::Vector2d(0.1, 0.1), Eigen::Vector2d(0.0, 0.0));
	Eigen::Vector2d r;
	for (double lambda : {0.2, 0.0, -0.2, std::nan("")})
	{
		const double* x[3] = {Th.data(), Tt.data(), &lambda};
		EXPECT_FALSE(f.evaluate(x, r.data(), nullptr)) << "lambda = " << lambda;
	}
	const double lambda = 0.05;	 // 20 m ahead: in front of the target
	const double* x[3] = {Th.data(), Tt.data(), &lambda};
	EXPECT_TRUE(f.evaluate(x, r.data(), nullptr));
	EXPECT_THROW(MonocularInverseDepthFactor(Eigen::Vector2d(NAN, 0), Eigen::Vector2d(0, 0)), std::invalid_argument);
}

TEST(MonocularInverseDepth, PointAtInfinityLimitIsPureRotation)
{
	// As λ → 0 the prediction tends to the rotated bearing R_tᵀR_h·b, whatever the baseline.
	Rng rng(17);
	const Pose Th = rng.pose();
	const Pose Tt = make_pose(rotation(Th) * axis_angle(0.2, rng.unit()), rng.vec(-5, 5));
	const Eigen::Vector2d b(0.1, -0.2);
	const Eigen::Vector3d dir = rotation(Tt).transpose() * rotation(Th) * Eigen::Vector3d(b.x(), b.y(), 1.0);
	MonocularInverseDepthFactor f(b, Eigen::Vector2d::Zero());
	const double lambda = 1e-12;
	const double* x[3] = {Th.data(), Tt.data(), &lambda};
	Eigen::Vector2d r;
	ASSERT_TRUE(f.evaluate(x, r.data(), nullptr));
	EXPECT_LE((r - project(dir)).cwiseAbs().maxCoeff(), 1e-10);
}
