// BAL reader/writer: the shipped Ladybug problem (sizes, behind-camera count, Ceres's initial cost),
// an exact write/read round trip, and each malformed case rejected with its line number.
#include <gtest/gtest.h>

#include "bal_test_data.h"
#include <swba/io/bal.h>
#include <swba/problems/bal.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace
{
const std::string kLadybug = std::string(SWBA_DATA_DIR) + "/bal/problem-49-7776-pre.txt";

// A valid 2-camera, 2-point, 3-observation problem; parameters one per line
// (cameras on lines 5..22, points on lines 23..28).
std::string small_problem_text()
{
	std::ostringstream s;
	s << "2 2 3\n"
	  << "0 0 -1.5e+01 2.0e+00\n"
	  << "1 0 3.0 -4.0\n"
	  << "1 1 5.0 6.0\n";
	for (int c = 0; c < 2; c++)
	{
		const double cam[9] = {0.01 * c, 0.02, -0.03, 0.1, 0.2, -3.0 - c, 500.0, -0.1, 0.01};
		for (double v : cam) s << v << "\n";
	}
	s << "0.5\n0.25\n-1\n1\n2\n-3\n";
	return s.str();
}

// Returns the parse error's line, or -1 if the text was accepted.
int error_line(const std::string& text, std::string* what = nullptr)
{
	try
	{
		swba::io::parse_bal(text, "t.bal");
	}
	catch (const swba::io::BalParseError& e)
	{
		if (what) *what = e.what();
		return e.line();
	}
	return -1;
}

std::string replace_line(const std::string& text, int line, const std::string& replacement)
{
	std::istringstream in(text);
	std::ostringstream out;
	std::string l;
	for (int i = 1; std::getline(in, l); i++) out << (i == line ? replacement : l) << "\n";
	return out.str();
}

std::string drop_last_lines(const std::string& text, int n)
{
	std::istringstream in(text);
	std::vector<std::string> lines;
	std::string l;
	while (std::getline(in, l)) lines.push_back(l);
	std::string out;
	for (size_t i = 0; i + static_cast<size_t>(n) < lines.size(); i++) out += lines[i] + "\n";
	return out;
}
}  // namespace

TEST(BalReader, ReadsLadybugSizesAndValues)
{
	const auto bal = swba::io::read_bal(kLadybug);
	EXPECT_EQ(bal.num_cameras, 49);
	EXPECT_EQ(bal.num_points, 7776);
	ASSERT_EQ(bal.observations.size(), 31843u);
	EXPECT_EQ(bal.cameras.size(), 49u * 9u);
	EXPECT_EQ(bal.points.size(), 7776u * 3u);
	// First line of the file after the header: "0 0     -3.326500e+02 2.620900e+02".
	EXPECT_EQ(bal.observations[0].camera, 0);
	EXPECT_EQ(bal.observations[0].point, 0);
	EXPECT_EQ(bal.observations[0].x, -332.65);
	EXPECT_EQ(bal.observations[0].y, 262.09);
}

TEST(BalReader, CountsObservationsBehindTheirCamera)
{
	// REFERENCE.md: 31 observations of problem-49-7776 have the point behind the camera.
	EXPECT_EQ(swba::problems::count_observations_behind_camera(swba::io::read_bal(kLadybug)), 31);
}

TEST(BalReader, InitialCostMatchesCeres)
{
	// Ceres's initial cost on problem-49-7776 (REFERENCE.md): 8.509125e5 (7 significant digits).
	const auto bal = swba::io::read_bal(kLadybug);
	swba::Problem problem;
	const auto vars = swba::problems::add_bal_to_problem(bal, problem);
	EXPECT_EQ(vars.num_unobserved_cameras, 0);
	EXPECT_EQ(vars.num_unobserved_points, 0);
	EXPECT_EQ(problem.num_factors(), 31843u);
	int dropped = -1;
	const double cost = problem.cost(&dropped);
	EXPECT_EQ(dropped, 0);
	EXPECT_NEAR(cost, 8.509125e5, 0.05e1);
}

TEST(BalReader, WriteReadRoundTripIsExact)
{
	const auto bal = swba::io::read_bal(kShrink);
	const std::string path = ::testing::TempDir() + "swba_bal_roundtrip.txt";
	swba::io::write_bal(path, bal);
	const auto back = swba::io::read_bal(path);
	std::remove(path.c_str());
	EXPECT_EQ(back.num_cameras, bal.num_cameras);
	EXPECT_EQ(back.num_points, bal.num_points);
	ASSERT_EQ(back.observations.size(), bal.observations.size());
	for (size_t k = 0; k < bal.observations.size(); k++)
	{
		EXPECT_EQ(back.observations[k].camera, bal.observations[k].camera);
		EXPECT_EQ(back.observations[k].point, bal.observations[k].point);
		EXPECT_EQ(back.observations[k].x, bal.observations[k].x);
		EXPECT_EQ(back.observations[k].y, bal.observations[k].y);
	}
	EXPECT_EQ(back.cameras, bal.cameras);
	EXPECT_EQ(back.points, bal.points);
}

TEST(BalReader, AcceptsTheSmallProblem)
{
	const auto bal = swba::io::parse_bal(small_problem_text());
	EXPECT_EQ(bal.observations.size(), 3u);
	EXPECT_EQ(bal.camera(1)[5], -4.0);
	EXPECT_EQ(bal.point(1)[2], -3.0);
}

TEST(BalReader, RejectsMalformedInputWithTheLine)
{
	const std::string good = small_problem_text();
	ASSERT_EQ(error_line(good), -1);
	std::string what;

	EXPECT_EQ(error_line("", &what), 1) << "empty file";
	EXPECT_EQ(error_line(replace_line(good, 1, "2 2"), &what), 1) << "header with 2 values";
	EXPECT_NE(what.find("t.bal:1:"), std::string::npos) << what;
	EXPECT_EQ(error_line(replace_line(good, 1, "2 x 3")), 1) << "non-integer count";
	EXPECT_EQ(error_line(replace_line(good, 1, "2 0 3")), 1) << "zero points";

	// Count mismatch: the header declares 4 observations but there are 3 (line 5 is a parameter).
	EXPECT_EQ(error_line(replace_line(good, 1, "2 2 4"), &what), 5);
	EXPECT_NE(what.find("count mismatch"), std::string::npos) << what;
	// Count mismatch the other way: one observation fewer declared → an extra value at the end.
	EXPECT_EQ(error_line(replace_line(good, 1, "2 2 2"), &what), 25);
	EXPECT_NE(what.find("count mismatch"), std::string::npos) << what;
	EXPECT_EQ(error_line(good + "7\n", &what), 29) << "trailing value";

	EXPECT_EQ(error_line(replace_line(good, 3, "1 0 3.0"), &what), 3) << "observation with 3 values";
	EXPECT_EQ(error_line(replace_line(good, 3, "2 0 3.0 -4.0"), &what), 3) << "camera index out of range";
	EXPECT_NE(what.find("camera index 2 out of range"), std::string::npos) << what;
	EXPECT_EQ(error_line(replace_line(good, 4, "1 -1 5.0 6.0"), &what), 4) << "negative point index";
	EXPECT_NE(what.find("point index -1 out of range"), std::string::npos) << what;
	EXPECT_EQ(error_line(replace_line(good, 4, "1 2 5.0 6.0")), 4) << "point index = num_points";
	EXPECT_EQ(error_line(replace_line(good, 2, "0.5 0 1 2")), 2) << "fractional camera index";

	EXPECT_EQ(error_line(replace_line(good, 2, "0 0 nan 2.0"), &what), 2) << "NaN observation";
	EXPECT_NE(what.find("non-finite"), std::string::npos) << what;
	EXPECT_EQ(error_line(replace_line(good, 11, "inf"), &what), 11) << "infinite camera parameter";
	EXPECT_NE(what.find("non-finite"), std::string::npos) << what;
	EXPECT_EQ(error_line(replace_line(good, 27, "-inf")), 27) << "infinite point coordinate";
	EXPECT_EQ(error_line(replace_line(good, 28, "1e999")), 28) << "overflowing number";
	EXPECT_EQ(error_line(replace_line(good, 20, "1.0abc")), 20) << "garbage in a number";

	// Truncated: in the observations (file ends after line 3), in the cameras, in the points.
	EXPECT_EQ(error_line(drop_last_lines(good, 25), &what), 4);
	EXPECT_NE(what.find("truncated"), std::string::npos) << what;
	EXPECT_EQ(error_line(drop_last_lines(good, 8), &what), 21);
	EXPECT_NE(what.find("missing camera 1 parameter 7"), std::string::npos) << what;
	EXPECT_EQ(error_line(drop_last_lines(good, 1), &what), 28);
	EXPECT_NE(what.find("missing point 1 coordinate 2"), std::string::npos) << what;
}

// Found by fuzz_bal: the header's counts sized the arrays before any data was read, so a 20-byte
// file declaring 10^9 observations (or cameras) asked for tens of GB. It is now a truncation error.
TEST(BalReader, HugeDeclaredCountsAreATruncationNotAnAllocation)
{
	std::string what;
	EXPECT_EQ(error_line("1 1 1000000000\n0 0 1 2\n", &what), 3);
	EXPECT_NE(what.find("declares 1000000000 observations, found only 1"), std::string::npos) << what;
	EXPECT_EQ(error_line("1000000000 1 1\n0 0 1 2\n0.5\n", &what), 4);
	EXPECT_NE(what.find("truncated"), std::string::npos) << what;
}

// A count above swba's limit is named as such, not as a non-positive count.
TEST(BalReader, CountAboveTheLimitNamesTheLimit)
{
	std::string what;
	EXPECT_EQ(error_line("1000000000 1000000000 2000000000\n0 0 1 1\n", &what), 1);
	EXPECT_NE(what.find("num_observations must be at most 1000000000 (swba's limit), found '2000000000'"),
			  std::string::npos)
		<< what;
	EXPECT_EQ(error_line("0 1 1\n", &what), 1);
	EXPECT_NE(what.find("num_cameras must be positive, found '0'"), std::string::npos) << what;
}

TEST(BalReader, ReportsMissingFileAndUnsupportedCompression)
{
	EXPECT_THROW(swba::io::read_bal("/nonexistent/problem.txt"), std::runtime_error);
	if (swba::io::bal_bzip2_supported()) GTEST_SKIP() << "bzip2 supported: covered by BalReader.ReadsBzip2";
	const std::string path = ::testing::TempDir() + "swba_bal_fake.bz2";
	{
		std::ofstream f(path);
		f << "BZh91AY&SY";
	}
	try
	{
		swba::io::read_bal(path);
		ADD_FAILURE() << "compressed input accepted without libbz2";
	}
	catch (const std::runtime_error& e)
	{
		EXPECT_NE(std::string(e.what()).find("bzip2"), std::string::npos) << e.what();
	}
	std::remove(path.c_str());
}
