// Tests of swba compare's library (swba/apps/compare.h): the paired statistics against hand-computed
// values, and what it reads, counts and refuses.
#include <swba/apps/compare.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "test_temp_dir.h"

using namespace swba::apps;
namespace fs = std::filesystem;

namespace
{
/** A range-bearing summary.json with one row per (label, rmse); rmse < 0 writes a failed row. */
void write_summary(const fs::path& dir, const std::string& rawlog, const std::vector<std::pair<std::string, double>>& rows,
				   const std::string& rows_key = "estimators", const std::string& rot_key = "ape_rot")
{
	fs::create_directories(dir);
	std::ofstream f(dir / "summary.json");
	f << "{\"rawlog\": \"" << rawlog << "\", \"" << rows_key << "\": [";
	for (std::size_t i = 0; i < rows.size(); i++)
	{
		const auto& [label, v] = rows[i];
		if (i) f << ", ";
		f << "{\"label\": \"" << label << "\", ";
		if (v < 0)
			f << "\"ape_trans\": null, \"failed\": true}";
		else
			f << "\"ape_trans\": {\"rmse\": " << v << "}, \"" << rot_key << "\": {\"rmse\": " << 10 * v
			  << "}, \"failed\": false}";
	}
	f << "]}\n";
}
}  // namespace

TEST(Compare, PairedStatisticsMatchHandComputedValues)
{
	const fs::path d = temp_dir();
	// base 1, 2, 4 and other 2, 2, 2: ln ratios ln 2, 0, −ln 2 (mean 0, sample sd ln 2), geomeans 2 and 2.
	const double base[3] = {1, 2, 4};
	for (int i = 0; i < 3; i++)
	{
		write_summary(d / "a" / std::to_string(i), "log" + std::to_string(i), {{"window W=5", base[i]}});
		write_summary(d / "b" / std::to_string(i), "log" + std::to_string(i), {{"window W=5", 2.0}});
	}
	const ResultSet a = read_results((d / "a").string(), CompareMetric::ApeTrans);
	const ResultSet b = read_results((d / "b").string(), CompareMetric::ApeTrans);
	EXPECT_EQ(a.summaries, 3u);
	const PairedComparison c = compare_label(a, b, "window W=5");
	ASSERT_EQ(c.rawlogs.size(), 3u);
	EXPECT_NEAR(c.base_geomean, 2.0, 1e-12);
	EXPECT_NEAR(c.other_geomean, 2.0, 1e-12);
	EXPECT_NEAR(c.mean_log_ratio, 0.0, 1e-12);
	ASSERT_TRUE(c.log_ratio_std_error);
	EXPECT_NEAR(*c.log_ratio_std_error, std::log(2.0) / std::sqrt(3.0), 1e-12);
	EXPECT_EQ(c.better, 1u);
	EXPECT_EQ(c.worse, 1u);
	EXPECT_EQ(c.equal, 1u);
}

TEST(Compare, OneSidedMeanAndTheOtherMetric)
{
	const fs::path d = temp_dir();
	// other = 1.1 x base on every log: mean ln ratio ln 1.1, standard error 0; rotation read as well.
	for (int i = 0; i < 4; i++)
	{
		write_summary(d / "a" / std::to_string(i), "log" + std::to_string(i), {{"w", 0.1 * (i + 1)}});
		write_summary(d / "b" / std::to_string(i), "log" + std::to_string(i), {{"w", 0.11 * (i + 1)}});
	}
	for (CompareMetric m : {CompareMetric::ApeTrans, CompareMetric::ApeRot})
	{
		const PairedComparison c = compare_label(read_results((d / "a").string(), m), read_results((d / "b").string(), m), "w");
		ASSERT_EQ(c.rawlogs.size(), 4u);
		EXPECT_NEAR(c.mean_log_ratio, std::log(1.1), 1e-12);
		EXPECT_NEAR(*c.log_ratio_std_error, 0.0, 1e-9);
		EXPECT_EQ(c.worse, 4u);
		EXPECT_NEAR(c.base_geomean, (m == CompareMetric::ApeRot ? 1.0 : 0.1) * std::pow(24.0, 0.25), 1e-12);
	}
}

TEST(Compare, FailedRowsAndOneSidedRawlogsAreCountedNotPaired)
{
	const fs::path d = temp_dir();
	write_summary(d / "a/1", "log1", {{"w", 0.5}});
	write_summary(d / "b/1", "log1", {{"w", -1}});  // failed in other
	write_summary(d / "a/2", "log2", {{"w", -1}});
	write_summary(d / "b/2", "log2", {{"w", -1}});  // failed in both
	write_summary(d / "a/3", "log3", {{"w", 0.3}});
	write_summary(d / "b/3", "log3", {{"w", 0.2}});
	write_summary(d / "a/4", "log4", {{"w", 0.3}});  // base only
	const PairedComparison c = compare_label(read_results((d / "a").string(), CompareMetric::ApeTrans),
											 read_results((d / "b").string(), CompareMetric::ApeTrans), "w");
	ASSERT_EQ(c.rawlogs, std::vector<std::string>{"log3"});
	EXPECT_EQ(c.no_figure_other, 1u);
	EXPECT_EQ(c.no_figure_both, 1u);
	EXPECT_EQ(c.no_figure_base, 0u);
	EXPECT_FALSE(c.log_ratio_std_error);  // one pair: no standard error

	CompareOptions o;
	o.base = (d / "a").string();
	o.other = (d / "b").string();
	o.json_path = (d / "c.json").string();
	std::ostringstream out, log;
	EXPECT_EQ(run_compare(o, out, log), 0);
	EXPECT_NE(log.str().find("1 rawlog only in base, not compared: log4"), std::string::npos) << log.str();
	EXPECT_NE(log.str().find("1 in other only, 1 in both"), std::string::npos) << log.str();
	EXPECT_NE(out.str().find("w                              1"), std::string::npos) << out.str();
	EXPECT_NE(slurp(d / "c.json").find("\"base_only_rawlogs\": [\n    \"log4\""), std::string::npos) << slurp(d / "c.json");
}

TEST(Compare, ASweepsJobsAndItsMergeAreReadTogether)
{
	const fs::path d = temp_dir();
	write_summary(d / "sweep/jobs/log1/w10", "log1", {{"window W=10", 0.3}});
	write_summary(d / "sweep/jobs/log1/w5", "log1", {{"window W=5", 0.4}});
	write_summary(d / "sweep/merged/log1", "log1", {{"window W=5", 0.4}, {"window W=10", 0.3}});
	const ResultSet s = read_results((d / "sweep").string(), CompareMetric::ApeTrans);
	EXPECT_EQ(s.summaries, 3u);
	// Rows in the order of the summary with most rows (the merge's), one figure per row.
	EXPECT_EQ(s.labels, (std::vector<std::string>{"window W=5", "window W=10"}));
	ASSERT_EQ(s.figures.size(), 1u);
	EXPECT_EQ(s.figures.at("log1").at("window W=5").value, 0.4);
	EXPECT_EQ(s.figures.at("log1").at("window W=10").value, 0.3);
}

TEST(Compare, ConflictingFiguresMalformedFilesAndEmptyDirectoriesAreRefused)
{
	const fs::path d = temp_dir();
	write_summary(d / "two/a", "log1", {{"w", 0.4}});
	write_summary(d / "two/b", "log1", {{"w", 0.5}});
	try
	{
		read_results((d / "two").string(), CompareMetric::ApeTrans);
		ADD_FAILURE() << "no error";
	}
	catch (const std::runtime_error& e)
	{
		EXPECT_NE(std::string(e.what()).find("give 'w' different figures"), std::string::npos) << e.what();
	}
	fs::create_directories(d / "bad");
	std::ofstream(d / "bad/summary.json") << "{\"rawlog\": 3";
	EXPECT_THROW(read_results((d / "bad").string(), CompareMetric::ApeTrans), std::runtime_error);
	fs::create_directories(d / "empty");
	EXPECT_THROW(read_results((d / "empty").string(), CompareMetric::ApeTrans), std::runtime_error);
	EXPECT_THROW(read_results((d / "none").string(), CompareMetric::ApeTrans), std::runtime_error);
	std::ofstream(d / "bad/summary.json") << "{\"rawlog\": \"x\", \"other\": []}";
	EXPECT_THROW(read_results((d / "bad").string(), CompareMetric::ApeTrans), std::runtime_error);
}

TEST(Compare, InertialSummariesAreRead)
{
	const fs::path d = temp_dir();
	write_summary(d / "a", "imu.rawlog", {{"inertial window W=10", 0.2}}, "rows", "ape_rot_deg");
	write_summary(d / "b", "imu.rawlog", {{"inertial window W=10", 0.1}}, "rows", "ape_rot_deg");
	const PairedComparison c = compare_label(read_results((d / "a").string(), CompareMetric::ApeRot),
											 read_results((d / "b").string(), CompareMetric::ApeRot), "inertial window W=10");
	ASSERT_EQ(c.rawlogs.size(), 1u);
	EXPECT_NEAR(c.mean_log_ratio, std::log(0.5), 1e-12);
	EXPECT_EQ(c.better, 1u);
}

TEST(Compare, BatchRowsPairWhateverStartEachRawlogTook)
{
	const fs::path d = temp_dir();
	for (const auto& [side, start, v] : {std::tuple{"a", "DR", 0.2}, {"b", "W=30", 0.1}})
	{
		fs::create_directories(d / side);
		std::ofstream(d / side / "summary.json")
			<< "{\"rawlog\": \"log1\", \"estimators\": [{\"label\": \"batch (" << start
			<< " start)\", \"start\": \"x\", \"ape_trans\": {\"rmse\": " << v << "}, \"failed\": false}]}\n";
	}
	const ResultSet a = read_results((d / "a").string(), CompareMetric::ApeTrans);
	EXPECT_EQ(a.labels, std::vector<std::string>{"batch"});
	const PairedComparison c = compare_label(a, read_results((d / "b").string(), CompareMetric::ApeTrans), "batch");
	ASSERT_EQ(c.rawlogs.size(), 1u);
	EXPECT_NEAR(c.mean_log_ratio, std::log(0.5), 1e-12);
}
