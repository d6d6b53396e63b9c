// TUM and MRPT ground-truth readers/writers: valid files, malformed files (file:line), edge cases;
// the number formatting the writers use.
#include <gtest/gtest.h>
#include <swba/eval/alignment.h>
#include <swba/eval/text_format.h>
#include <swba/eval/trajectory.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <sstream>
#include <vector>

using namespace swba::eval;

namespace
{
Trajectory tum(const std::string& text)
{
	std::istringstream in(text);
	return read_tum(in, "test.tum");
}

/** Expects read_tum to throw TrajectoryFileError at `line` with `fragment` in the message. */
void expect_tum_error(const std::string& text, std::size_t line, const std::string& fragment)
{
	try
	{
		tum(text);
		ADD_FAILURE() << "no error for:\n" << text;
	}
	catch (const TrajectoryFileError& e)
	{
		EXPECT_EQ(e.file, "test.tum");
		EXPECT_EQ(e.line, line) << e.what();
		const std::string what = e.what();
		EXPECT_EQ(what.rfind("test.tum:" + std::to_string(line) + ": ", 0), 0u) << what;
		EXPECT_NE(what.find(fragment), std::string::npos) << what;
	}
}
}  // namespace

TEST(TumIo, ReadsRowsCommentsAndBlankLines)
{
	const Trajectory t = tum(
		"# timestamp x y z qx qy qz qw\n"
		"\n"
		"0.5 1 2 3 0 0 0 1\n"
		"   # indented comment\r\n"
		"1.0\t4 5 6 0 0 0.7071067811865476 0.7071067811865476\r\n");
	ASSERT_EQ(t.size(), 2u);
	EXPECT_EQ(t.stamps[0], 0.5);
	EXPECT_EQ(t.poses[0].x(), 1.0);
	EXPECT_EQ(t.poses[1].z(), 6.0);
	EXPECT_NEAR(t.poses[1].yaw(), M_PI / 2, 1e-12);
}

TEST(TumIo, EmptyAndCommentOnlyFilesGiveEmptyTrajectories)
{
	EXPECT_TRUE(tum("").empty());
	EXPECT_TRUE(tum("# nothing\n\n").empty());
}

TEST(TumIo, OnePoseFile)
{
	const Trajectory t = tum("3 0 0 0 0 0 0 1");  // no final newline
	ASSERT_EQ(t.size(), 1u);
	EXPECT_EQ(t.stamps[0], 3.0);
}

TEST(TumIo, SlightlyNonUnitQuaternionIsNormalised)
{
	const Trajectory t = tum("0 0 0 0 0 0 0.3826834 0.9238796\n1 0 0 0 0 0 0 1.0005\n");
	ASSERT_EQ(t.size(), 2u);
	const Eigen::Matrix3d R = t.poses[0].getRotationMatrix().asEigen();
	EXPECT_NEAR((R.transpose() * R - Eigen::Matrix3d::Identity()).norm(), 0.0, 1e-14);
	EXPECT_NEAR(t.poses[0].yaw(), M_PI / 4, 1e-6);
}

TEST(TumIo, MalformedRowsAreRejectedWithFileAndLine)
{
	expect_tum_error("# c\n0 0 0 0 0 0 0 1\n1 0 0 0 0 0 1\n", 3, "expected 8 columns");
	expect_tum_error("0 0 0 0 0 0 0 1 9\n", 1, "found 9");
	expect_tum_error("0 0 0 0 0 0 0 1\n1 0 abc 0 0 0 0 1\n", 2, "column 3 (y) is not a number");
	expect_tum_error("0 0 0 0 0 0 0 1\n1 0 1.5x 0 0 0 0 1\n", 2, "not a number");
	expect_tum_error("0 nan 0 0 0 0 0 1\n", 1, "not finite");
	expect_tum_error("0 0 0 inf 0 0 0 1\n", 1, "not finite");
	expect_tum_error("0 0 0 0 0 0 0 0\n", 1, "zero quaternion");
	expect_tum_error("0 0 0 0 0 0 0 0.5\n", 1, "not unit");
	expect_tum_error("0 0 0 0 0 0 0 1\n2 0 0 0 0 0 0 1\n\n1 0 0 0 0 0 0 1\n", 4, "before the previous one");
}

TEST(TumIo, EqualStampsAreAccepted)
{
	EXPECT_EQ(tum("1 0 0 0 0 0 0 1\n1 1 0 0 0 0 0 1\n").size(), 2u);
}

TEST(TumIo, MissingFileNamesThePath)
{
	try
	{
		read_tum("/nonexistent/dir/x.tum");
		FAIL();
	}
	catch (const TrajectoryFileError& e)
	{
		EXPECT_NE(std::string(e.what()).find("/nonexistent/dir/x.tum"), std::string::npos);
	}
}

TEST(TumIo, WriteThenReadRoundTrips)
{
	Trajectory t;
	t.push_back(0.25, mrpt::poses::CPose3D(1.5, -2.0, 0.125, 0.3, -0.2, 2.9));
	t.push_back(1.25, mrpt::poses::CPose3D(0, 0, 0, M_PI - 1e-4, 0.0, 0.0));
	std::ostringstream out;
	write_tum(out, t, 12);
	const Trajectory back = tum(out.str());
	ASSERT_EQ(back.size(), 2u);
	for (std::size_t i = 0; i < 2; i++)
	{
		EXPECT_NEAR(back.stamps[i], t.stamps[i], 1e-12);
		EXPECT_NEAR((to_matrix(back.poses[i]) - to_matrix(t.poses[i])).norm(), 0.0, 1e-11);
	}
	// Format: single spaces, 8 columns, qw >= 0.
	std::istringstream lines(out.str());
	std::string line;
	while (std::getline(lines, line))
	{
		std::istringstream ss(line);
		std::vector<double> v;
		double x;
		while (ss >> x) v.push_back(x);
		ASSERT_EQ(v.size(), 8u);
		EXPECT_GE(v[7], 0.0);
		EXPECT_EQ(line.find("  "), std::string::npos);
	}
}

TEST(MrptGroundTruth, RowsGetStepIndexAsTime)
{
	std::istringstream in(
		"% Columns are: x(m) y(m) z(m) yaw(rad) pitch(rad) roll(rad)\n"
		"0 0 0 0 0 0\n"
		"\n"
		"1 2 3 0.5 -0.25 0.125\n");
	const Trajectory t = read_mrpt_ground_truth(in, "gt.txt");
	ASSERT_EQ(t.size(), 2u);
	EXPECT_EQ(t.stamps[0], 0.0);
	EXPECT_EQ(t.stamps[1], 1.0);
	EXPECT_NEAR(t.poses[1].yaw(), 0.5, 1e-12);
	EXPECT_NEAR(t.poses[1].pitch(), -0.25, 1e-12);
	EXPECT_NEAR(t.poses[1].roll(), 0.125, 1e-12);
	EXPECT_EQ(t.poses[1].y(), 2.0);
}

TEST(MrptGroundTruth, WrongColumnCountNamesFileAndLine)
{
	std::istringstream in("% c\n0 0 0 0 0 0\n1 2 3 0.5 -0.25\n");
	try
	{
		read_mrpt_ground_truth(in, "gt.txt");
		FAIL();
	}
	catch (const TrajectoryFileError& e)
	{
		EXPECT_EQ(e.line, 3u);
		EXPECT_EQ(std::string(e.what()).rfind("gt.txt:3: expected 6 columns", 0), 0u) << e.what();
	}
}

TEST(TextFormat, AppendFixedAndScientificWriteWhatPrintfWrites)
{
	using limits = std::numeric_limits<double>;
	std::vector<double> values = {0.0,	   -0.0,	  1.0,		 -1.0,		0.1,			   1.0 / 3.0,
								  0.5,	   2.5,		  -2.5e-10,	 1e22,		123456.5,		   5e-324,
								  1e-310,  1e100,	  -1e300,	 limits::max(), -limits::max(), limits::min(),
								  limits::infinity(), -limits::infinity(), limits::quiet_NaN(), -limits::quiet_NaN()};
	std::mt19937_64 rng(7);
	std::uniform_real_distribution<double> mantissa(-10.0, 10.0);
	std::uniform_int_distribution<int> exponent(-40, 40);
	for (int i = 0; i < 2000; i++) values.push_back(std::ldexp(mantissa(rng), exponent(rng)));
	char buf[512];
	for (int precision : {0, 1, 6, 9, 17, 30})
		for (double v : values)
		{
			std::string fixed = "x", scientific = "x";
			append_fixed(fixed, v, precision);
			append_scientific(scientific, v, precision);
			std::snprintf(buf, sizeof(buf), "x%.*f", precision, v);
			ASSERT_EQ(fixed, buf) << "precision " << precision;
			std::snprintf(buf, sizeof(buf), "x%.*e", precision, v);
			ASSERT_EQ(scientific, buf) << "precision " << precision;
		}
}
