// swba run's plots as files: the error over time fills its axis, a run without ground truth still has
// its top view, and without gnuplot every plot's data and script are written.
#include <swba/apps/run.h>
#include <swba/eval/plot.h>

#include <gtest/gtest.h>

#include "test_temp_dir.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

namespace
{
namespace fs = std::filesystem;
using mrpt::poses::CPose3D;
using swba::apps::RunOptions;
using swba::apps::RunReport;
using swba::apps::RunRow;

/** The y values of the first block of a plot's .dat file (the error curve of an error-over-time plot). */
std::vector<double> first_block_y(const std::string& dat)
{
	std::vector<double> y;
	std::istringstream in(dat);
	std::string line;
	while (std::getline(in, line))
	{
		if (line.empty()) break;
		if (line[0] == '#') continue;
		double a = 0, b = 0;
		if (std::istringstream(line) >> a >> b) y.push_back(b);
	}
	return y;
}

/** The `set yrange [a:b]` of a script; fails the test when it is absent. */
std::pair<double, double> script_yrange(const std::string& gp)
{
	const std::string key = "set yrange [";
	const auto at = gp.find(key);
	EXPECT_NE(at, std::string::npos) << key << " missing in\n" << gp;
	if (at == std::string::npos) return {0, std::numeric_limits<double>::infinity()};
	double lo = 0, hi = 0;
	char colon = 0;
	std::istringstream(gp.substr(at + key.size())) >> lo >> colon >> hi;
	return {lo, hi};
}

/** PATH without gnuplot for the lifetime of the object. */
class NoGnuplotOnPath
{
   public:
	NoGnuplotOnPath() : saved_(std::getenv("PATH") ? std::getenv("PATH") : "") { ::setenv("PATH", "/nonexistent", 1); }
	~NoGnuplotOnPath() { ::setenv("PATH", saved_.c_str(), 1); }
	NoGnuplotOnPath(const NoGnuplotOnPath&) = delete;
	NoGnuplotOnPath& operator=(const NoGnuplotOnPath&) = delete;

   private:
	std::string saved_;
};

/** Two rows without APE (a run without ground truth): a straight line and a slightly bent one. */
RunReport report_without_ground_truth()
{
	RunReport rep;
	rep.rawlog = "/data/line.rawlog";
	rep.steps = 20;
	for (const char* name : {"window", "batch"})
	{
		RunRow r;
		r.name = name;
		r.label = name == std::string("window") ? "window W=5" : "batch";
		r.window = r.name == "window" ? 5 : 0;
		r.trajectory = r.name == "window" ? "online" : "smoothed";
		r.file = r.name == "window" ? "window_5.tum" : "batch.tum";
		for (int k = 0; k < 20; k++) r.estimate.push_back(k + 1.0, CPose3D(0.5 * k, r.window ? 0.01 * k : 0, 0, 0, 0, 0));
		rep.rows.push_back(r);
	}
	return rep;
}
}  // namespace

TEST(RunPlotFiles, ApeCurveSpansAtLeastHalfItsAxisOnTheDemo)
{
	RunOptions o;
	o.rawlog = std::string(SWBA_MRPT_DATASETS) + "/kf-slam_6D_demo.rawlog";
	o.windows = {10};
	o.run_ekf = false;
	o.run_batch = false;
	o.progress = false;
	o.out_dir = (temp_dir() / "out").string();
	std::ostringstream out, log;
	swba::apps::run_app(o, out, log);
	const fs::path plots = fs::path(o.out_dir) / "plots";
	const std::string gp = slurp(plots / "ape_window_10.gp");
	const std::vector<double> errors = first_block_y(slurp(plots / "ape_window_10.dat"));
	ASSERT_EQ(errors.size(), 599u);
	const auto [lo, hi] = script_yrange(gp);
	const auto [emin, emax] = std::minmax_element(errors.begin(), errors.end());
	EXPECT_GE((*emax - *emin) / (hi - lo), 0.5) << "y axis [" << lo << ", " << hi << "], errors " << *emin << " … " << *emax;
	// Every line drawn is one the documentation names: the errors, rmse, median, mean and the std band.
	EXPECT_EQ(gp.find("trace"), std::string::npos) << gp;
}

TEST(RunPlotFiles, TopViewWithoutGroundTruth)
{
	RunReport rep = report_without_ground_truth();
	RunOptions o;
	o.out_dir = (temp_dir() / "out").string();
	swba::apps::write_run_outputs(o, {}, rep);
	const std::string dat = slurp(fs::path(o.out_dir) / "trajectories.dat");
	EXPECT_NE(dat.find("# window W=5\n"), std::string::npos) << dat;
	EXPECT_NE(dat.find("# batch\n"), std::string::npos) << dat;
	EXPECT_TRUE(fs::exists(fs::path(o.out_dir) / "trajectories.gp"));
	if (!swba::eval::find_gnuplot().empty())
	{
		EXPECT_TRUE(fs::exists(fs::path(o.out_dir) / "trajectories.png"));
	}
	// No APE, hence no plot of it.
	EXPECT_FALSE(fs::exists(fs::path(o.out_dir) / "ape_rmse_vs_window.dat"));
	EXPECT_FALSE(fs::exists(fs::path(o.out_dir) / "plots"));
}

TEST(RunPlotFiles, DataAndScriptsWithoutGnuplot)
{
	RunReport rep = report_without_ground_truth();
	RunOptions o;
	o.out_dir = (temp_dir() / "out").string();
	{
		const NoGnuplotOnPath no_gnuplot;
		ASSERT_TRUE(swba::eval::find_gnuplot().empty());
		swba::apps::write_run_outputs(o, {}, rep);
	}
	EXPECT_TRUE(fs::exists(fs::path(o.out_dir) / "trajectories.dat"));
	EXPECT_TRUE(fs::exists(fs::path(o.out_dir) / "trajectories.gp"));
	EXPECT_FALSE(fs::exists(fs::path(o.out_dir) / "trajectories.png"));
	// One note for the whole run, naming where the scripts are.
	const auto n = std::count_if(rep.notes.begin(), rep.notes.end(),
								 [](const std::string& s) { return s.find("gnuplot") != std::string::npos; });
	EXPECT_EQ(n, 1) << ::testing::PrintToString(rep.notes);
	EXPECT_NE(rep.notes.front().find("gnuplot not found: plots not drawn; their data (.dat) and scripts (.gp) are in " + o.out_dir),
			  std::string::npos)
		<< rep.notes.front();
}
