// Text/CSV/JSON reports and headless plots (with and without gnuplot).
#include <gtest/gtest.h>
#include <swba/eval/plot.h>
#include <swba/eval/report.h>
#include <swba/eval/text_format.h>

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


TEST(Plot, RangesIgnoreAClippedSeries)
{
	LinePlot p;
	p.series.push_back({"good", {0, 10}, {0, 5}});
	p.series.push_back({"other", {2, 4}, {1, 2}});
	p.references.push_back({"EKF", 3});
	// Nothing clipped: gnuplot autoscales.
	auto [x0, y0] = plot_ranges(p);
	EXPECT_FALSE(x0);
	EXPECT_FALSE(y0);
	// A diverged series far outside: the ranges are the others' ±5 %, not its.
	PlotSeries bad{"diverged", {-1000, 5000}, {0, 9000}};
	bad.clipped = true;
	p.series.push_back(bad);
	p.references.push_back({"diverged ref", 800, true});
	const auto [x, y] = plot_ranges(p);
	ASSERT_TRUE(x && y);
	EXPECT_DOUBLE_EQ(x->min, -0.5);
	EXPECT_DOUBLE_EQ(x->max, 10.5);
	EXPECT_DOUBLE_EQ(y->min, -0.25);
	EXPECT_DOUBLE_EQ(y->max, 5.25);
	// An explicit range wins.
	p.yrange = AxisRange{0, 1};
	EXPECT_DOUBLE_EQ(plot_ranges(p).second->max, 1.0);
	// data_range: non-finite values are skipped; one value gets a margin from its magnitude.
	EXPECT_FALSE(data_range({std::nan(""), HUGE_VAL}));
	const auto one = data_range({2.0, std::nan("")});
	ASSERT_TRUE(one);
	EXPECT_DOUBLE_EQ(one->min, 1.9);
	EXPECT_DOUBLE_EQ(one->max, 2.1);
}

TEST(Plot, ScriptHasRangesNotesAndTheKeyOutside)
{
	const std::string dir = fresh_dir("clipped");
	PlotOptions o;
	o.gnuplot = "/nonexistent/gnuplot";
	LinePlot p;
	p.title = "top view";
	p.series.push_back({"good", {0, 10}, {0, 5}});
	PlotSeries bad{"diverged", {0, 5000}, {0, 9000}};
	bad.clipped = true;
	p.series.push_back(bad);
	p.notes = {"ekf: failed at step 3, not drawn", "diverged: drawn clipped"};
	plot_lines(dir, "p", p, o);
	const std::string gp = slurp(dir + "/p.gp");
	EXPECT_NE(gp.find("set xrange [-0.5:10.5]\n"), std::string::npos) << gp;
	EXPECT_NE(gp.find("set yrange [-0.25:5.25]\n"), std::string::npos) << gp;
	EXPECT_NE(gp.find("set label 1 \"ekf: failed at step 3, not drawn\" at character 1, character 2 left"),
			  std::string::npos)
		<< gp;
	EXPECT_NE(gp.find("set label 2 \"diverged: drawn clipped\" at character 1, character 1 left"), std::string::npos);
	EXPECT_NE(gp.find("set key outside"), std::string::npos);
	// The clipped series is still drawn: its data is in the file.
	EXPECT_NE(slurp(dir + "/p.dat").find("5000 9000"), std::string::npos);
	fs::remove_all(dir);
}

TEST(Plot, ErrorOverTimeHasRmseMeanMedianAndStdBand)
{
	const std::string dir = fresh_dir("errors_lines");
	PlotOptions o;
	o.gnuplot = "/nonexistent/gnuplot";
	const MetricResult r = small_result();  // errors 0, 0.5, 1, 1.5
	plot_error_over_time(dir, "e", r, o);
	const std::string gp = slurp(dir + "/e.gp");
	const auto num = [](double v) { return format_significant(v, 6); };
	for (const std::string& line : std::vector<std::string>{"title \"rmse (" + num(r.stats.rmse) + ")\"", "title \"mean (0.75)\"",
								   "title \"median (0.75)\"", "filledcurves"})
		EXPECT_NE(gp.find(line), std::string::npos) << line << "\n" << gp;
	// The band spans the data's x extent at mean ± std.
	const std::string dat = slurp(dir + "/e.dat");
	const std::string lo = format_significant(r.stats.mean - r.stats.std, 10);
	const std::string hi = format_significant(r.stats.mean + r.stats.std, 10);
	EXPECT_NE(dat.find("0 " + lo + " " + hi + "\n3 " + lo + " " + hi + "\n"), std::string::npos) << dat;
	fs::remove_all(dir);
}

TEST(Plot, ColormapWritesErrorsAsAThirdColumn)
{
	const std::string dir = fresh_dir("colormap");
	PlotOptions o;
	o.gnuplot = "/nonexistent/gnuplot";
	const MetricResult r = small_result();
	ColormapTopView c;
	c.reference = {"reference", r.ref};
	c.estimate = {"estimate", r.est};
	c.errors = r.errors;
	c.error_label = "APE (m)";
	c.color_range = AxisRange{0, 2};
	plot_trajectory_colormap(dir, "cm", c, o);
	EXPECT_NE(slurp(dir + "/cm.dat").find("# estimate\n0 0 0\n1 0.5 0.5\n2 1 1\n3 1.5 1.5\n"), std::string::npos)
		<< slurp(dir + "/cm.dat");
	const std::string gp = slurp(dir + "/cm.gp");
	EXPECT_NE(gp.find("using 1:2:3 with lines lw 2 lc palette"), std::string::npos) << gp;
	EXPECT_NE(gp.find("set cbrange [0:2]"), std::string::npos);
	c.errors.pop_back();
	EXPECT_THROW(plot_trajectory_colormap(dir, "cm", c, o), std::invalid_argument);
	fs::remove_all(dir);
}

TEST(Plot, SameInputSameFiles)
{
	const std::string a = fresh_dir("det_a"), b = fresh_dir("det_b");
	PlotOptions o;
	o.gnuplot = "/nonexistent/gnuplot";
	plot_error_over_time(a, "e", small_result(), o);
	plot_error_over_time(b, "e", small_result(), o);
	EXPECT_EQ(slurp(a + "/e.dat"), slurp(b + "/e.dat"));
	EXPECT_EQ(slurp(a + "/e.gp"), slurp(b + "/e.gp"));
	fs::remove_all(a);
	fs::remove_all(b);
}
