// evo 1.36.5's numbers on share/data/evo_reference (kf-slam_6D_demo GT vs MRPT's EKF), to 1e-9 relative.
#include <gtest/gtest.h>
#include <swba/eval/alignment.h>
#include <swba/eval/evaluation.h>
#include <swba/eval/report.h>
#include <swba/eval/trajectory.h>

#include <string>

using namespace swba::eval;

namespace
{
const std::string kDir = std::string(SWBA_DATA_DIR) + "/evo_reference/";

struct EvoReference : ::testing::Test
{
	Trajectory gt = read_tum(kDir + "gt_kf-slam_6D_demo.tum");
	Trajectory ekf = read_tum(kDir + "ekf_kf-slam_6D_demo.tum");
};

void expect_rel(double value, double expected, double rel = 1e-9)
{
	EXPECT_NEAR(value, expected, rel * std::abs(expected)) << "value " << value << " expected " << expected;
}
}  // namespace

TEST_F(EvoReference, FilesHaveExpectedSizes)
{
	EXPECT_EQ(gt.size(), 600u);
	EXPECT_EQ(ekf.size(), 599u);
}

TEST_F(EvoReference, TranslationNotAligned)
{
	const MetricResult r = compute_ape(gt, ekf);
	EXPECT_EQ(r.errors.size(), 599u);
	expect_rel(r.stats.rmse, 0.0160637612904);
	expect_rel(r.stats.mean, 0.0135404639951);
	expect_rel(r.stats.max, 0.0662427900515);
	EXPECT_EQ(r.title, "APE w.r.t. translation part (m)\n(not aligned)");
	// The estimate after step k (t = k+1) pairs with GT row k+1: ref stamps equal est stamps.
	for (std::size_t i = 0; i < r.ref.size(); i++) ASSERT_EQ(r.ref.stamps[i], r.est.stamps[i]);
}

TEST_F(EvoReference, TranslationSE3Aligned)
{
	ApeOptions o;
	o.alignment.align = true;
	const MetricResult r = compute_ape(gt, ekf, o);
	expect_rel(r.stats.rmse, 0.0140646580617);
	EXPECT_EQ(r.title, "APE w.r.t. translation part (m)\n(with SE(3) Umeyama alignment)");
	EXPECT_DOUBLE_EQ(r.alignment.transform.scale, 1.0);
}

TEST_F(EvoReference, TranslationSim3Aligned)
{
	ApeOptions o;
	o.alignment.align = true;
	o.alignment.correct_scale = true;
	const MetricResult r = compute_ape(gt, ekf, o);
	expect_rel(r.stats.rmse, 0.0139984045934);
	EXPECT_EQ(r.title, "APE w.r.t. translation part (m)\n(with Sim(3) Umeyama alignment)");
	EXPECT_NE(r.alignment.transform.scale, 1.0);
}

// The angle reference was evidently computed from ground-truth rotations at full precision: the GT
// file's source (mrpt-common's *_ground_truth_robot_path.txt, read here directly) reproduces it to
// ~6e-12, while the shipped gt_*.tum, whose quaternions are rounded to 9 decimals (up to 6e-10 from
// the source), gives 1.7e-9 relative — see the next test and doc/evaluation.md.
TEST_F(EvoReference, RotationAngleDegreesNotAligned)
{
	const Trajectory gt_full =
		read_mrpt_ground_truth(std::string(SWBA_MRPT_DATASETS) + "/kf-slam_6D_demo_ground_truth_robot_path.txt");
	ApeOptions o;
	o.relation = PoseRelation::RotationAngleDeg;
	const MetricResult r = compute_ape(gt_full, ekf, o);
	EXPECT_EQ(r.errors.size(), 599u);
	expect_rel(r.stats.rmse, 0.227397461006);
	EXPECT_EQ(r.title, "APE w.r.t. rotation angle (deg)\n(not aligned)");
	// The same in radians.
	o.relation = PoseRelation::RotationAngleRad;
	expect_rel(compute_ape(gt_full, ekf, o).stats.rmse, 0.227397461006 * M_PI / 180.0);
}

TEST_F(EvoReference, RotationAngleFromNineDecimalQuaternionsAndTheHybridCheck)
{
	ApeOptions o;
	o.relation = PoseRelation::RotationAngleDeg;
	// Shipped 9-decimal GT quaternions: 1.7e-9 relative off (a rounding effect, not a definition one;
	// tolerance 3e-9 for that reason only).
	expect_rel(compute_ape(gt, ekf, o).stats.rmse, 0.227397461006, 3e-9);
	// GT with the TUM file's positions and full-precision rotations reproduces all four numbers to 1e-9
	// (in fact ≤ 3e-11): the translation references were computed from 9-decimal positions, the angle
	// one from full-precision rotations.
	const Trajectory gt_full =
		read_mrpt_ground_truth(std::string(SWBA_MRPT_DATASETS) + "/kf-slam_6D_demo_ground_truth_robot_path.txt");
	Trajectory hybrid = gt;
	for (std::size_t i = 0; i < gt.size(); i++)
		hybrid.poses[i] = mrpt::poses::CPose3D::FromRotationAndTranslation(
			gt_full.poses[i].getRotationMatrix().asEigen(), Eigen::Vector3d(gt.poses[i].x(), gt.poses[i].y(), gt.poses[i].z()));
	expect_rel(compute_ape(hybrid, ekf, o).stats.rmse, 0.227397461006);
	ApeOptions t;
	expect_rel(compute_ape(hybrid, ekf, t).stats.rmse, 0.0160637612904);
	t.alignment.align = true;
	expect_rel(compute_ape(hybrid, ekf, t).stats.rmse, 0.0140646580617);
	t.alignment.correct_scale = true;
	expect_rel(compute_ape(hybrid, ekf, t).stats.rmse, 0.0139984045934);
}

TEST_F(EvoReference, TextReportHasEvoLayout)
{
	const std::string text = format_text_report(compute_ape(gt, ekf));
	EXPECT_EQ(text.rfind("APE w.r.t. translation part (m)\n(not aligned)\n\n       max\t0.066243\n      mean\t0.013540\n", 0),
			  0u)
		<< text;
	EXPECT_NE(text.find("      rmse\t0.016064\n"), std::string::npos) << text;
}

TEST_F(EvoReference, MrptGroundTruthFileMatchesTumConversion)
{
	const Trajectory mrpt =
		read_mrpt_ground_truth(std::string(SWBA_MRPT_DATASETS) + "/kf-slam_6D_demo_ground_truth_robot_path.txt");
	ASSERT_EQ(mrpt.size(), gt.size());
	for (std::size_t i = 0; i < gt.size(); i++)
	{
		ASSERT_EQ(mrpt.stamps[i], gt.stamps[i]);
		// The TUM file has 9 decimals.
		ASSERT_NEAR((to_matrix(mrpt.poses[i]) - to_matrix(gt.poses[i])).norm(), 0.0, 1e-8) << i;
	}
	// And the APE from the MRPT file agrees with evo to the TUM file's rounding.
	expect_rel(compute_ape(mrpt, ekf).stats.rmse, 0.0160637612904, 1e-6);
}
