// swba run's consistency figures (RunRow::nees): the NEES of a row's own covariance against the ground
// truth, averaged over its poses, against values computed by hand.
#include <swba/apps/run.h>

#include "rows.h"  // modules/apps/src/run (tests/apps/tests.cmake)

#include <gtest/gtest.h>

#include <mrpt/poses/CPose3D.h>

#include <cmath>

using mrpt::poses::CPose3D;
using swba::apps::RunRow;

namespace
{
/** Two poses after steps 0 and 1 (t = 1, 2), each with the covariance diag(0.01, 0.04, 0.09 | 1e-4, 1e-4,
 * 1e-4) in its own frame: the first at identity rotation 0.1 m off the truth along x, the second turned by
 * 90° (as the truth) 0.4 m off along the world's y — its own x, where its variance is 0.01. */
RunRow two_pose_row(std::vector<CPose3D>& gt)
{
	RunRow row("window", "window W=5", "online", 5);
	row.estimate.push_back(1.0, CPose3D(1.0, 0, 0, 0, 0, 0));
	row.estimate.push_back(2.0, CPose3D(2.0, 0, 0, M_PI / 2, 0, 0));
	gt = {CPose3D(), CPose3D(1.1, 0, 0, 0, 0, 0), CPose3D(2.0, 0.4, 0, M_PI / 2, 0, 0)};
	swba::estimators::PoseCovariance c = swba::estimators::PoseCovariance::Zero();
	c.diagonal() << 0.01, 0.04, 0.09, 1e-4, 1e-4, 1e-4;
	row.covariance = {c, c};
	return row;
}
}  // namespace

TEST(RunNees, IsTheMeanOfEachPosesNeesAndTheShareInsideOneRunsBand)
{
	std::vector<CPose3D> gt;
	RunRow row = two_pose_row(gt);
	swba::apps::compute_row_nees(row, gt);
	ASSERT_TRUE(row.nees.has_value()) << row.nees_error;
	const auto& n = *row.nees;
	// Position (world frame, the covariance turned with the pose): 0.1²/0.01 = 1 and 0.4²/0.01 = 16; the pose's
	// tangent error is the translation in the pose's frame with a zero rotation: 1 and 16 as well.
	EXPECT_EQ(n.poses, 2u);
	EXPECT_NEAR(n.position_mean, 8.5, 1e-9);
	EXPECT_NEAR(n.pose_mean, 8.5, 1e-9);
	EXPECT_EQ(n.position_dof, 3);
	EXPECT_EQ(n.pose_dof, 6);
	// One run's two-sided 95 % band: χ²₃ [0.216, 9.348] holds 1, not 16; χ²₆ [1.237, 14.449] neither.
	EXPECT_DOUBLE_EQ(n.position_in_band, 0.5);
	EXPECT_DOUBLE_EQ(n.pose_in_band, 0.0);
	EXPECT_TRUE(row.nees_error.empty());
}

TEST(RunNees, IsNotComputedWithoutCovarianceAndSaysWhyForOneThatIsNotPositiveDefinite)
{
	std::vector<CPose3D> gt;
	RunRow none = two_pose_row(gt);
	none.covariance.clear();
	swba::apps::compute_row_nees(none, gt);
	EXPECT_FALSE(none.nees.has_value());
	EXPECT_TRUE(none.nees_error.empty());

	RunRow bad = two_pose_row(gt);
	bad.covariance[1](1, 1) = -0.04;
	swba::apps::compute_row_nees(bad, gt);
	EXPECT_FALSE(bad.nees.has_value());
	EXPECT_NE(bad.nees_error.find("row 2"), std::string::npos) << bad.nees_error;
}
