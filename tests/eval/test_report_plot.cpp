// Text/CSV/JSON reports and headless plots (with and without gnuplot).
#include <gtest/gtest.h>
#include <swba/eval/plot.h>
#include <swba/eval/report.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

using namespace swba::eval;
namespace fs = std::filesystem;

namespace
{
Statistics stats_of_3_1_2() { return compute_statistics({3.0, 1.0, 2.0}); }

std::string slurp(const std::string& path)
{
	std::ifstream f(path);
	std::stringstream ss;
	ss << f.rdbuf();
	return ss.str();
}

/** A fresh empty directory under the build tree's temp dir, named after the running test. */
std::string fresh_dir(const std::string& name)
{
	const fs::path p = fs::temp_directory_path() / ("swba_test_eval_" + name);
	fs::remove_all(p);
	return p.string();
}

MetricResult small_result()
{
	Trajectory ref, est;
	for (int i = 0; i < 4; i++)
	{
		ref.push_back(i, mrpt::poses::CPose3D(i, 0, 0, 0, 0, 0));
		est.push_back(i, mrpt::poses::CPose3D(i, 0.5 * i, 0, 0, 0, 0));
	}
	return compute_ape(ref, est);
}
}  // namespace

TEST(Report, TextBlockIsEvoPrettyStr)
{
	EXPECT_EQ(format_statistics_text("APE w.r.t. translation part (m)\n(not aligned)", stats_of_3_1_2()),
			  "APE w.r.t. translation part (m)\n(not aligned)\n\n"
			  "       max\t3.000000\n"
			  "      mean\t2.000000\n"
			  "    median\t2.000000\n"
			  "       min\t1.000000\n"
			  "      rmse\t2.160247\n"
			  "       sse\t14.000000\n"
			  "       std\t0.816497\n");
}

TEST(Report, StatisticsJsonIsOneObject)
{
	const auto j = nlohmann::ordered_json::parse(statistics_json(stats_of_3_1_2()));
	ASSERT_TRUE(j.is_object());
	std::vector<std::string> keys;
	for (const auto& item : j.items()) keys.push_back(item.key());
	EXPECT_EQ(keys, (std::vector<std::string>{"max", "mean", "median", "min", "rmse", "sse", "std", "count"}));
	EXPECT_EQ(j["max"].get<double>(), 3.0);
	EXPECT_EQ(j["min"].get<double>(), 1.0);
	EXPECT_EQ(j["rmse"].get<double>(), stats_of_3_1_2().rmse);  // round trip: the very same double
	EXPECT_NEAR(j["rmse"].get<double>(), std::sqrt(14.0 / 3.0), 1e-15);
	EXPECT_EQ(j["sse"].get<double>(), 14.0);
	EXPECT_EQ(j["std"].get<double>(), stats_of_3_1_2().std);
	ASSERT_TRUE(j["count"].is_number_unsigned());
	EXPECT_EQ(j["count"].get<std::size_t>(), 3u);

	Statistics bad;
	bad.max = std::nan("");
	bad.mean = HUGE_VAL;
	const auto b = nlohmann::json::parse(statistics_json(bad));
	EXPECT_TRUE(b["max"].is_null());
	EXPECT_TRUE(b["mean"].is_null());
	EXPECT_TRUE(b["min"].is_number());
}

TEST(Report, StatisticsCsvOneRowPerName)
{
	std::ostringstream out;
	write_statistics_csv(out, {{"EKF", stats_of_3_1_2()}, {"window, 10", compute_statistics({1.0})}});
	EXPECT_EQ(out.str(),
			  "name,count,max,mean,median,min,rmse,sse,std\n"
			  "EKF,3,3,2,2,1,2.1602468994692869,14,0.81649658092772603\n"
			  "\"window, 10\",1,1,1,1,1,1,1,0\n");
}

TEST(Report, ErrorsCsvAndResultJson)
{
	const MetricResult r = small_result();
	std::ostringstream out;
	write_errors_csv(out, r);
	std::istringstream lines(out.str());
	std::string line;
	std::getline(lines, line);
	EXPECT_EQ(line, "t,error,ref_x,ref_y,ref_z,est_x,est_y,est_z");
	std::getline(lines, line);
	EXPECT_EQ(line, "0,0,0,0,0,0,0,0");
	std::getline(lines, line);
	EXPECT_EQ(line, "1,0.5,1,0,0,1,0.5,0");
	const auto j = nlohmann::ordered_json::parse(result_json(r));
	std::vector<std::string> keys;
	for (const auto& item : j.items()) keys.push_back(item.key());
	EXPECT_EQ(keys, (std::vector<std::string>{"metric", "title", "relation", "unit", "alignment", "ref_input_poses",
											  "est_input_poses", "associated_poses", "stats", "stamps", "errors"}));
	EXPECT_EQ(j["errors"], nlohmann::ordered_json::parse("[0, 0.5, 1, 1.5]"));
	EXPECT_EQ(j["stamps"], nlohmann::ordered_json::parse("[0, 1, 2, 3]"));
	EXPECT_EQ(j["title"], "APE w.r.t. translation part (m)\n(not aligned)");  // the newline survives the escape
	EXPECT_EQ(j["metric"], r.metric);
	EXPECT_EQ(j["associated_poses"], 4u);
	EXPECT_EQ(j["stats"]["rmse"].get<double>(), r.stats.rmse);
	const auto& a = j["alignment"];
	EXPECT_EQ(a["align"], false);
	EXPECT_EQ(a["scale"].get<double>(), 1.0);
	EXPECT_EQ(a["rotation_row_major"].size(), 9u);
	EXPECT_EQ(a["translation"].size(), 3u);
	EXPECT_EQ(a["origin_transform_row_major"].size(), 16u);
	EXPECT_EQ(a["origin_transform_row_major"][0].get<double>(), r.alignment.origin(0, 0));
}

TEST(Report, SaveResultsWritesDeterministicFiles)
{
	const std::string dir = fresh_dir("save");
	const auto files = save_results(small_result(), dir + "/nested");
	ASSERT_EQ(files.size(), 5u);
	for (const char* name : {"ape_stats.json", "ape_stats.csv", "ape_errors.csv", "ape_result.json", "ape_est_aligned.tum"})
		EXPECT_TRUE(fs::exists(fs::path(dir) / "nested" / name)) << name;
	EXPECT_EQ(slurp(dir + "/nested/ape_stats.json"), statistics_json(small_result().stats) + "\n");
	const auto saved = nlohmann::json::parse(slurp(dir + "/nested/ape_result.json"));
	EXPECT_EQ(saved["errors"].size(), 4u);
	EXPECT_EQ(read_tum(dir + "/nested/ape_est_aligned.tum").size(), 4u);
	fs::remove_all(dir);
}

TEST(Plot, WithoutGnuplotGivesANoteNotAFailure)
{
	const std::string dir = fresh_dir("nognuplot");
	PlotOptions o;
	o.gnuplot = "/nonexistent/gnuplot";
	const PlotOutput p = plot_rmse_vs_window(dir, "rmse_vs_window", {{"window", {5, 10, 20}, {0.03, 0.02, 0.018}}},
											 {{"EKF", 0.016}, {"batch", 0.009}}, "APE rmse vs window size",
											 "APE rmse (m)", o);
	EXPECT_FALSE(p.rendered);
	EXPECT_EQ(p.note.find('\n'), std::string::npos);
	EXPECT_NE(p.note.find("gnuplot not found"), std::string::npos) << p.note;
	EXPECT_TRUE(fs::exists(dir + "/rmse_vs_window.dat"));
	EXPECT_TRUE(fs::exists(dir + "/rmse_vs_window.gp"));
	EXPECT_FALSE(fs::exists(dir + "/rmse_vs_window.png"));
	// The script names both reference lines with their values.
	const std::string gp = slurp(dir + "/rmse_vs_window.gp");
	EXPECT_NE(gp.find("EKF (0.016)"), std::string::npos);
	EXPECT_NE(gp.find("batch (0.009)"), std::string::npos);
	fs::remove_all(dir);
}

TEST(Plot, RendersPngAndSvgWhenGnuplotIsInstalled)
{
	if (find_gnuplot().empty()) GTEST_SKIP() << "gnuplot not on PATH";
	const std::string dir = fresh_dir("gnuplot");
	const MetricResult r = small_result();
	const PlotOutput a = plot_trajectories_top_view(dir, "traj", {"reference", r.ref}, {{"estimate", r.est}});
	const PlotOutput b = plot_error_over_time(dir, "errors", r);
	const PlotOutput c = plot_rmse_vs_window(dir, "rmse", {{"SW", {5, 10}, {0.2, 0.1}}, {"SW+FEJ", {5, 10}, {0.15, 0.08}}},
											 {{"EKF", 0.12}});
	for (const auto* p : {&a, &b, &c}) EXPECT_TRUE(p->rendered) << p->note;
	for (const char* f : {"traj.png", "traj.svg", "errors.png", "errors.svg", "rmse.png", "rmse.svg"})
	{
		ASSERT_TRUE(fs::exists(fs::path(dir) / f)) << f;
		EXPECT_GT(fs::file_size(fs::path(dir) / f), 1000u) << f;
	}
	// PNG signature.
	EXPECT_EQ(slurp(dir + "/traj.png").substr(1, 3), "PNG");
	fs::remove_all(dir);
}

