// Tests of BetweenPoseFactor and PosePriorFactor (the SO(3) helpers they use are tested in tests/core).
#include "factor_test_fixtures.h"

#include <swba/factors/between_pose.h>
#include <swba/factors/pose_prior.h>

#include <mrpt/poses/Lie/SE.h>
#include <mrpt/poses/Lie/SO.h>

#include <cstdio>

using namespace swba;
using namespace swba::factor_test;
using mrpt::poses::CPose3D;

namespace
{
Eigen::Matrix<double, 6, 1> eval6(const Factor& f, const std::vector<const double*>& x)
{
	Eigen::Matrix<double, 6, 1> r;
	EXPECT_TRUE(f.evaluate(x.data(), r.data(), nullptr));
	return r;
}

struct BetweenCase
{
	std::string name;
	Pose Ti, Tj;
	CPose3D Z;
};

/** Random and nasty configurations of (Ti, Tj, Z). */
std::vector<BetweenCase> between_cases()
{
	Rng rng(2024);
	std::vector<BetweenCase> cases;
	auto Z_of = [](const Eigen::Matrix3d& R, const Eigen::Vector3d& t) { return to_cpose(make_pose(R, t)); };
	for (int k = 0; k < 6; k++)
		cases.push_back({"random " + std::to_string(k), rng.pose(), rng.pose(), Z_of(rng.rotation(), rng.vec(-3, 3))});
	// Tiny angles everywhere: poses, measurement and residual rotations of ~1e-5 rad.
	cases.push_back({"small angles", make_pose(axis_angle(1e-5, rng.unit()), rng.vec(-1, 1)),
					 make_pose(axis_angle(2e-5, rng.unit()), rng.vec(-1, 1)), Z_of(axis_angle(1e-5, rng.unit()), rng.vec(-1, 1))});
	// Poses rotated by exactly π and by π − 1e-9 about random axes.
	{
		const Eigen::Vector3d a = rng.unit();
		cases.push_back({"poses at pi", make_pose(axis_angle(M_PI, a), rng.vec(-2, 2)),
						 make_pose(axis_angle(M_PI - 1e-9, rng.unit()), rng.vec(-2, 2)), Z_of(rng.rotation(), rng.vec(-1, 1))});
	}
	// Zero residual exactly (Z = Ti⁻¹Tj).
	{
		Pose Ti = rng.pose(), Tj = rng.pose();
		cases.push_back({"zero residual", Ti, Tj, (-to_cpose(Ti)) + to_cpose(Tj)});
	}
	// Residual rotation near π: Z = Ti⁻¹Tj·Exp(ω) with ‖ω‖ = π − 1e-4 (and π − 1e-3).
	for (double gap : {1e-3, 1e-4})
	{
		Pose Ti = rng.pose(), Tj = rng.pose();
		const CPose3D E = to_cpose(make_pose(axis_angle(M_PI - gap, rng.unit()), rng.vec(-1, 1)));
		cases.push_back({"residual rotation pi-" + std::to_string(gap), Ti, Tj, (-to_cpose(Ti)) + to_cpose(Tj) + (-E)});
	}
	// Large translations (100 m) with a small residual rotation.
	cases.push_back({"far poses", rng.pose(100.0), rng.pose(100.0), Z_of(axis_angle(0.2, rng.unit()), rng.vec(-50, 50))});
	return cases;
}
}  // namespace

TEST(BetweenPose, ResidualIsMrptPseudoLogOfZinvTiinvTj)
{
	for (const auto& c : between_cases())
	{
		BetweenPoseFactor f(c.Z);
		const auto r = eval6(f, {c.Ti.data(), c.Tj.data()});
		const auto v = mrpt::poses::Lie::SE<3>::log((-c.Z) + ((-to_cpose(c.Ti)) + to_cpose(c.Tj)));
		for (int i = 0; i < 6; i++) EXPECT_NEAR(r[i], v[i], 1e-9 * std::max(1.0, std::abs(v[i]))) << c.name;
		// The same as SE3Manifold::minus(Tj, Ti·Z).
		const Pose TiZ = make_pose(to_cpose(c.Ti) + c.Z);
		Eigen::Matrix<double, 6, 1> m;
		SE3Manifold::instance()->minus(c.Tj.data(), TiZ.data(), m.data());
		EXPECT_LE((r - m).cwiseAbs().maxCoeff(), 1e-9) << c.name;
	}
}

TEST(BetweenPose, ZeroResidualAtTruth)
{
	Rng rng(11);
	for (int k = 0; k < 5; k++)
	{
		const Pose Ti = rng.pose(), Tj = rng.pose();
		BetweenPoseFactor f((-to_cpose(Ti)) + to_cpose(Tj));
		EXPECT_LE(eval6(f, {Ti.data(), Tj.data()}).cwiseAbs().maxCoeff(), 1e-12);
	}
}

TEST(BetweenPose, JacobiansMatchNumeric)
{
	const auto cases = between_cases();
	ASSERT_GE(cases.size(), 5u);
	for (const auto& c : cases)
	{
		BetweenPoseFactor f(c.Z);
		expect_jacobians_match(f, {c.Ti.data(), c.Tj.data()}, {se3(), se3()}, "BetweenPoseFactor", c.name);
	}
}

TEST(BetweenPose, JacobiansMatchMrptGraphSlamJacobians)
{
	// MRPT's jacob_dDinvP1invP2_de1e2 (what its graph-SLAM levmarq uses); note it takes −Z as "Dinv".
	int checked = 0;
	for (const auto& c : between_cases())
	{
		BetweenPoseFactor f(c.Z);
		Eigen::Matrix<double, 6, 6, Eigen::RowMajor> Ji, Jj;
		double* jac[2] = {Ji.data(), Jj.data()};
		Eigen::Matrix<double, 6, 1> r;
		ASSERT_TRUE(f.evaluate(std::vector<const double*>{c.Ti.data(), c.Tj.data()}.data(), r.data(), jac));
		mrpt::poses::Lie::SE<3>::matrix_TxT Mi, Mj;
		mrpt::poses::Lie::SE<3>::jacob_dDinvP1invP2_de1e2(-c.Z, to_cpose(c.Ti), to_cpose(c.Tj), Mi, Mj);
		// MRPT differentiates through a 12×12 matrix chain with a Log Jacobian that loses digits as the
		// residual rotation nears π (measured: 1e-6 off at π − 1e-3, 1.7e-3 off at π − 1e-4, where ours
		// matches central differences to 1.4e-8), so the cross-check stops at a residual angle of 3 rad.
		if (r.tail<3>().norm() > 3.0) continue;
		checked++;
		EXPECT_LE((Ji - Mi.asEigen()).cwiseAbs().maxCoeff(), 1e-8) << c.name;
		EXPECT_LE((Jj - Mj.asEigen()).cwiseAbs().maxCoeff(), 1e-8) << c.name;
	}
	EXPECT_GE(checked, 5);
}

TEST(BetweenPose, WhitenedByInformation)
{
	Rng rng(3);
	const Pose Ti = rng.pose(), Tj = rng.pose();
	BetweenPoseFactor f(to_cpose(rng.pose()));
	Eigen::Matrix<double, 6, 6> info = Eigen::Matrix<double, 6, 6>::Zero();
	info.diagonal() << 4, 4, 4, 100, 100, 100;
	f.set_information(info);
	Eigen::Matrix<double, 6, 1> r, rw;
	const std::vector<const double*> x{Ti.data(), Tj.data()};
	ASSERT_TRUE(f.evaluate(x.data(), r.data(), nullptr));
	ASSERT_TRUE(f.evaluate_whitened(x.data(), rw.data(), nullptr));
	EXPECT_NEAR(rw.squaredNorm(), r.dot(info * r), 1e-9 * r.dot(info * r));
}

TEST(PosePrior, ZeroAtPriorAndMinusSemantics)
{
	Rng rng(5);
	for (int k = 0; k < 5; k++)
	{
		const Pose Z = rng.pose(), T = rng.pose();
		PosePriorFactor at_truth(to_cpose(Z));
		EXPECT_LE(eval6(at_truth, {Z.data()}).cwiseAbs().maxCoeff(), 1e-12);
		const Pose Zr = make_pose(to_cpose(Z));	 // Z as the factor stores it (through CPose3D)
		Eigen::Matrix<double, 6, 1> m;
		SE3Manifold::instance()->minus(T.data(), Zr.data(), m.data());
		EXPECT_LE((eval6(at_truth, {T.data()}) - m).cwiseAbs().maxCoeff(), 1e-12);
	}
}

TEST(PosePrior, JacobiansMatchNumeric)
{
	const auto cases = between_cases();
	for (const auto& c : cases)
	{
		// Prior at Ti·Z, evaluated at Tj: the same nasty residuals as the between cases.
		PosePriorFactor f(to_cpose(c.Ti) + c.Z);
		expect_jacobians_match(f, {c.Tj.data()}, {se3()}, "PosePriorFactor", c.name);
	}
}
