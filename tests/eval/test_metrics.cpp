// Statistics, pose relations, APE/RPE on hand-made cases.
#include <gtest/gtest.h>
#include <swba/eval/alignment.h>
#include <swba/eval/evaluation.h>
#include <swba/eval/metrics.h>

#include <Eigen/Geometry>
#include <random>

using namespace swba::eval;

TEST(Statistics, OddCountByHand)
{
	// e = 3, 1, 2: mean 2, median 2, sse 14, rmse sqrt(14/3), population std sqrt(2/3).
	const Statistics s = compute_statistics({3.0, 1.0, 2.0});
	EXPECT_EQ(s.count, 3u);
	EXPECT_DOUBLE_EQ(s.max, 3.0);
	EXPECT_DOUBLE_EQ(s.min, 1.0);
	EXPECT_DOUBLE_EQ(s.mean, 2.0);
	EXPECT_DOUBLE_EQ(s.median, 2.0);
	EXPECT_DOUBLE_EQ(s.sse, 14.0);
	EXPECT_DOUBLE_EQ(s.rmse, std::sqrt(14.0 / 3.0));
	EXPECT_DOUBLE_EQ(s.std, std::sqrt(2.0 / 3.0));
}

TEST(Statistics, EvenCountMedianIsMeanOfMiddleValues)
{
	// e = 4, 1, 10, 2: sorted 1 2 4 10, median (2+4)/2 = 3, mean 17/4, sse 121, std² = 113/16... by hand:
	// deviations from 4.25: -3.25 -2.25 -0.25 5.75 → squares 10.5625 5.0625 0.0625 33.0625 = 48.75, /4 = 12.1875.
	const Statistics s = compute_statistics({4.0, 1.0, 10.0, 2.0});
	EXPECT_DOUBLE_EQ(s.median, 3.0);
	EXPECT_DOUBLE_EQ(s.mean, 4.25);
	EXPECT_DOUBLE_EQ(s.sse, 121.0);
	EXPECT_DOUBLE_EQ(s.rmse, std::sqrt(121.0 / 4.0));
	EXPECT_DOUBLE_EQ(s.std, std::sqrt(12.1875));
	EXPECT_DOUBLE_EQ(s.min, 1.0);
	EXPECT_DOUBLE_EQ(s.max, 10.0);
}

TEST(Statistics, SingleValueAndEmpty)
{
	const Statistics s = compute_statistics({0.5});
	EXPECT_EQ(s.median, 0.5);
	EXPECT_EQ(s.std, 0.0);
	EXPECT_EQ(s.rmse, 0.5);
	EXPECT_THROW(compute_statistics({}), std::invalid_argument);
}

TEST(Statistics, ItemsInEvoOrder)
{
	std::vector<std::string> names;
	for (const auto& [n, v] : statistics_items(Statistics{})) names.push_back(n);
	EXPECT_EQ(names, (std::vector<std::string>{"max", "mean", "median", "min", "rmse", "sse", "std"}));
}

TEST(RotationAngle, AccurateNearZeroAndNearPi)
{
	for (double a : {0.0, 1e-12, 1e-8, 1e-5, 0.3, 2.0, M_PI - 1e-6, M_PI})
	{
		const Eigen::Matrix3d R = Eigen::AngleAxisd(a, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
		EXPECT_NEAR(rotation_angle(R), a, 1e-15 + 1e-12 * a) << a;
	}
}

TEST(PoseRelations, HandComputedValues)
{
	// E = rotation by 90° about z, translation (3, 4, 0).
	Eigen::Matrix4d E = Eigen::Matrix4d::Identity();
	E.topLeftCorner<3, 3>() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
	E.topRightCorner<3, 1>() << 3, 4, 0;
	EXPECT_NEAR(pose_error(E, PoseRelation::TranslationPart), 5.0, 1e-15);
	// R − I = [[-1,-1,0],[1,-1,0],[0,0,0]] → Frobenius 2.
	EXPECT_NEAR(pose_error(E, PoseRelation::RotationPart), 2.0, 1e-15);
	EXPECT_NEAR(pose_error(E, PoseRelation::FullTransformation), std::sqrt(4.0 + 25.0), 1e-14);
	EXPECT_NEAR(pose_error(E, PoseRelation::RotationAngleDeg), 90.0, 1e-12);
	EXPECT_NEAR(pose_error(E, PoseRelation::RotationAngleRad), M_PI / 2, 1e-15);
}

TEST(PoseRelations, ParseNames)
{
	EXPECT_EQ(parse_pose_relation("trans"), PoseRelation::TranslationPart);
	EXPECT_EQ(parse_pose_relation("angle_deg"), PoseRelation::RotationAngleDeg);
	EXPECT_EQ(pose_relation_name(parse_pose_relation("rot")), "rot");
	EXPECT_THROW(parse_pose_relation("translation"), std::invalid_argument);
}

namespace
{
Trajectory random_trajectory(int n, unsigned seed)
{
	std::mt19937 rng(seed);
	std::uniform_real_distribution<double> u(-1, 1);
	Trajectory t;
	for (int i = 0; i < n; i++) t.push_back(0.1 * i, mrpt::poses::CPose3D(u(rng), u(rng), u(rng), 3 * u(rng), u(rng), u(rng)));
	return t;
}
}  // namespace

TEST(Ape, IdenticalTrajectoriesGiveZeroErrorsForEveryRelationAndAlignment)
{
	const Trajectory t = random_trajectory(30, 1);
	for (auto rel : {PoseRelation::TranslationPart, PoseRelation::FullTransformation, PoseRelation::RotationPart,
					 PoseRelation::RotationAngleDeg, PoseRelation::RotationAngleRad})
		for (int mode = 0; mode < 4; mode++)
		{
			ApeOptions o;
			o.relation = rel;
			o.alignment.align = mode == 1 || mode == 2;
			o.alignment.correct_scale = mode == 2;
			o.alignment.align_origin = mode == 3;
			const MetricResult r = compute_ape(t, t, o);
			ASSERT_EQ(r.errors.size(), 30u);
			EXPECT_NEAR(r.stats.max, 0.0, 1e-9) << pose_relation_name(rel) << " mode " << mode;
			EXPECT_NEAR(r.stats.rmse, 0.0, 1e-9);
			RpeOptions ro;
			ro.relation = rel;
			ro.alignment = o.alignment;
			EXPECT_NEAR(compute_rpe(t, t, ro).stats.max, 0.0, 1e-9);
		}
}

TEST(Ape, ErrorIsEstInverseTimesRef)
{
	// ref = identity, est = pure rotation of 0.1 rad about x plus a shift: translation error is the
	// shift, angle is 0.1 rad.
	Trajectory ref, est;
	ref.push_back(0, mrpt::poses::CPose3D());
	est.push_back(0, mrpt::poses::CPose3D(0.3, 0, 0.4, 0, 0, 0.1));
	ApeOptions o;
	EXPECT_NEAR(compute_ape(ref, est, o).errors[0], 0.5, 1e-15);
	o.relation = PoseRelation::RotationAngleRad;
	EXPECT_NEAR(compute_ape(ref, est, o).errors[0], 0.1, 1e-15);
	// Full: E = est⁻¹ ref = [Rᵀ, −Rᵀ t]; ‖E − I‖² = ‖Rᵀ − I‖² + ‖t‖².
	o.relation = PoseRelation::FullTransformation;
	const double rot_part = std::sqrt(2 * (2 - 2 * std::cos(0.1)));
	EXPECT_NEAR(compute_ape(ref, est, o).errors[0], std::sqrt(rot_part * rot_part + 0.25), 1e-14);
}

TEST(Rpe, PairsAsEvo)
{
	using P = std::vector<std::pair<std::size_t, std::size_t>>;
	EXPECT_EQ(rpe_pairs(5, 1, false), (P{{0, 1}, {1, 2}, {2, 3}, {3, 4}}));
	EXPECT_EQ(rpe_pairs(7, 3, false), (P{{0, 3}, {3, 6}}));
	EXPECT_EQ(rpe_pairs(5, 3, true), (P{{0, 3}, {1, 4}}));
	EXPECT_TRUE(rpe_pairs(1, 1, false).empty());
	EXPECT_THROW(rpe_pairs(5, 0, false), std::invalid_argument);
}

TEST(Rpe, ConstantDriftPerStep)
{
	// Reference moves 1 m along x per step; the estimate 1.1 m: every consecutive RPE is 0.1 m,
	// every delta-2 RPE 0.2 m; the APE grows.
	Trajectory ref, est;
	for (int i = 0; i < 6; i++)
	{
		ref.push_back(i, mrpt::poses::CPose3D(i, 0, 0, 0, 0, 0));
		est.push_back(i, mrpt::poses::CPose3D(1.1 * i, 0, 0, 0, 0, 0));
	}
	RpeOptions o;
	const MetricResult r = compute_rpe(ref, est, o);
	ASSERT_EQ(r.errors.size(), 5u);
	for (double e : r.errors) EXPECT_NEAR(e, 0.1, 1e-12);
	EXPECT_EQ(r.stamps, (std::vector<double>{1, 2, 3, 4, 5}));
	EXPECT_EQ(r.title, "RPE w.r.t. translation part (m)\nfor delta = 1 (frames) using consecutive pairs\n(not aligned)");
	o.delta = 2;
	o.all_pairs = true;
	const MetricResult r2 = compute_rpe(ref, est, o);
	ASSERT_EQ(r2.errors.size(), 4u);
	for (double e : r2.errors) EXPECT_NEAR(e, 0.2, 1e-12);
	EXPECT_NE(r2.title.find("using all pairs"), std::string::npos);
	// One pose only: no pair, a clear error.
	Trajectory one;
	one.push_back(0, mrpt::poses::CPose3D());
	EXPECT_THROW(compute_rpe(one, one, {}), std::invalid_argument);
}

TEST(Ape, OnePoseAndEmptyInputs)
{
	Trajectory one;
	one.push_back(0, mrpt::poses::CPose3D(1, 2, 3, 0, 0, 0));
	Trajectory other;
	other.push_back(0, mrpt::poses::CPose3D(1, 2, 4, 0, 0, 0));
	const MetricResult r = compute_ape(one, other);
	EXPECT_DOUBLE_EQ(r.stats.rmse, 1.0);
	EXPECT_EQ(r.stats.std, 0.0);
	ApeOptions se3;
	se3.alignment.align = true;
	// One pose determines no rotation: an error, as evo's "Degenerate covariance rank" (not an rmse of 0).
	EXPECT_THROW(compute_ape(one, other, se3), std::invalid_argument);
	ApeOptions sim3 = se3;
	sim3.alignment.correct_scale = true;
	EXPECT_THROW(compute_ape(one, other, sim3), std::invalid_argument);
	EXPECT_THROW(compute_ape(Trajectory{}, other), std::invalid_argument);
	EXPECT_THROW(compute_ape(one, Trajectory{}), std::invalid_argument);
}
