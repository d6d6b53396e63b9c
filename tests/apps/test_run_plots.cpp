// swba run plots: failed rows left out with a note, diverged rows drawn clipped (they never set the
// axes), error over time per estimator and colormap top views.
#include "test_temp_dir.h"
#include <swba/apps/run.h>
#include <swba/eval/ground_truth.h>
#include <swba/eval/plot.h>
#include <swba/eval/text_format.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace
{
namespace fs = std::filesystem;
using mrpt::poses::CPose3D;
using swba::apps::RunReport;
using swba::apps::RunRow;

/** A square loop of n + 1 ground-truth rows, 1 m per step. */
std::vector<CPose3D> loop_gt(std::size_t n)
{
	std::vector<CPose3D> rows;
	for (std::size_t i = 0; i <= n; i++)
	{
		const double s = double(i % 40) / 10.0;
		const int side = int(i % 40) / 10;
		const double u = s - side;
		const double xy[4][2] = {{u, 0}, {1, u}, {1 - u, 1}, {0, 1 - u}};
		rows.emplace_back(10 * xy[side][0], 10 * xy[side][1], 0, 0, 0, 0);
	}
	return rows;
}

/** A row whose estimate is the ground truth shifted by `offset` in x and y, with its APE. */
RunRow row(const std::vector<CPose3D>& gt, const std::string& name, const std::string& label, int W, double offset)
{
	RunRow r;
	r.name = name;
	r.label = label;
	r.window = W;
	r.trajectory = name == "batch" ? "smoothed" : "online";
	r.file = name == "window" ? "window_" + std::to_string(W) + ".tum" : name + ".tum";
	for (std::size_t k = 0; k + 1 < gt.size(); k++)
		r.estimate.push_back(double(k + 1), gt[k + 1] + CPose3D(offset * double(1 + k % 3), offset, 0, 0, 0, 0));
	r.ape_trans_errors = swba::eval::ape_errors_against_ground_truth(gt, r.estimate, swba::eval::PoseRelation::TranslationPart);
	r.ape_trans = swba::eval::compute_statistics(r.ape_trans_errors);
	r.ape_full = r.ape_trans;
	r.has_ape = true;
	return r;
}

/** EKF failed at step 7, windows 5 and 10, batch; `diverged_w10`: W=10 (the top view's window) is 100 m off. */
RunReport report_of(const std::vector<CPose3D>& gt, bool diverged_w10)
{
	RunReport rep;
	rep.rawlog = "/data/loop.rawlog";
	rep.ground_truth = "/data/loop_ground_truth_robot_path.txt";
	rep.steps = gt.size() - 1;
	RunRow ekf = row(gt, "ekf", "ekf kfEKFNaive", 0, 0.01);
	ekf.failed = true;
	ekf.failed_step = 7;
	ekf.failure = "Vehicle pose quaternion norm is not >0";
	ekf.has_ape = false;
	ekf.ape_trans_errors.clear();
	rep.rows.push_back(ekf);
	rep.rows.push_back(row(gt, "window", "window W=5", 5, 0.03));
	rep.rows.push_back(row(gt, "window", "window W=10", 10, diverged_w10 ? 100.0 : 0.02));
	rep.rows.push_back(row(gt, "batch", "batch", 0, 0.01));
	return rep;
}

swba::apps::RunOptions options_in(const std::string& name)
{
	swba::apps::RunOptions o;
	o.out_dir = (fs::temp_directory_path() / ("swba_test_run_plots_" + name)).string();
	fs::remove_all(o.out_dir);
	o.plots = true;
	return o;
}

bool has_note(const RunReport& rep, const std::string& text)
{
	return std::any_of(rep.notes.begin(), rep.notes.end(),
					   [&](const std::string& n) { return n.find(text) != std::string::npos; });
}

/** The `set <axis>range [a:b]` of a script; fails the test when it is absent. */
swba::eval::AxisRange script_range(const std::string& gp, const std::string& axis)
{
	const std::string key = "set " + axis + "range [";
	const auto at = gp.find(key);
	EXPECT_NE(at, std::string::npos) << key << " missing in\n" << gp;
	if (at == std::string::npos) return {};
	swba::eval::AxisRange r;
	char colon = 0;
	std::istringstream(gp.substr(at + key.size())) >> r.min >> colon >> r.max;
	return r;
}
}  // namespace

TEST(RunPlots, FailedRowIsNotDrawnAndNoted)
{
	if (swba::eval::find_gnuplot().empty()) GTEST_SKIP() << "gnuplot not on PATH";
	const auto gt = loop_gt(40);
	RunReport rep = report_of(gt, false);
	const auto o = options_in("failed");
	swba::apps::write_run_outputs(o, gt, rep);
	const std::string note = "ekf kfEKFNaive: failed at step 7, not drawn";
	EXPECT_TRUE(has_note(rep, note));
	for (const char* base : {"trajectories", "ape_rmse_vs_window"})
	{
		EXPECT_EQ(slurp(fs::path(o.out_dir) / (std::string(base) + ".dat")).find("ekf"), std::string::npos) << base;
		EXPECT_NE(slurp(fs::path(o.out_dir) / (std::string(base) + ".gp")).find(note), std::string::npos) << base;
		EXPECT_TRUE(fs::exists(fs::path(o.out_dir) / (std::string(base) + ".png"))) << base;
	}
	EXPECT_FALSE(fs::exists(fs::path(o.out_dir) / "plots" / "ape_ekf.dat"));
	EXPECT_FALSE(fs::exists(fs::path(o.out_dir) / "plots" / "colormap_ekf.dat"));
	// Nothing diverged: no explicit range, gnuplot autoscales.
	EXPECT_FALSE(has_note(rep, "diverged"));
	EXPECT_EQ(slurp(fs::path(o.out_dir) / "trajectories.gp").find("set xrange"), std::string::npos);
	fs::remove_all(o.out_dir);
}

TEST(RunPlots, DivergedRowIsDrawnButNeverSetsTheAxes)
{
	if (swba::eval::find_gnuplot().empty()) GTEST_SKIP() << "gnuplot not on PATH";
	const auto gt = loop_gt(40);
	RunReport rep = report_of(gt, true);
	const auto o = options_in("diverged");
	swba::apps::write_run_outputs(o, gt, rep);
	EXPECT_TRUE(has_note(rep, "window W=10: diverged")) << ::testing::PrintToString(rep.notes);
	// Top view: the W=10 path (x, y ≥ 100) is in the data, but the ranges hold the square of 10 m only.
	const std::string dat = slurp(fs::path(o.out_dir) / "trajectories.dat");
	EXPECT_NE(dat.find("# window W=10 (diverged) (clipped)\n1"), std::string::npos);
	const std::string gp = slurp(fs::path(o.out_dir) / "trajectories.gp");
	EXPECT_NE(gp.find("window W=10: diverged"), std::string::npos);
	for (const char* axis : {"x", "y"})
	{
		const auto r = script_range(gp, axis);
		EXPECT_LT(r.max, 12.0) << axis;
		EXPECT_GT(r.min, -2.0) << axis;
	}
	// APE vs W: the y range comes from W=5 and batch, far below W=10's rmse (> 100 m).
	const auto y = script_range(slurp(fs::path(o.out_dir) / "ape_rmse_vs_window.gp"), "y");
	EXPECT_LT(y.max, 1.0);
	EXPECT_GT(y.max, rep.rows[1].ape_trans.rmse);
	// Its colormap keeps the others' colour scale (it saturates) and its axes come from the ground truth.
	const std::string cm = slurp(fs::path(o.out_dir) / "plots" / "colormap_window_10.gp");
	EXPECT_LT(script_range(cm, "x").max, 12.0);
	EXPECT_NE(cm.find("set cbrange [0:" + swba::eval::format_significant(rep.rows[3].ape_trans.max, 10) + "]"),
			  std::string::npos);
	fs::remove_all(o.out_dir);
}

TEST(RunPlots, ErrorOverTimePerEstimatorAndColormaps)
{
	if (swba::eval::find_gnuplot().empty()) GTEST_SKIP() << "gnuplot not on PATH";
	const auto gt = loop_gt(40);
	RunReport rep = report_of(gt, false);
	const auto o = options_in("per_row");
	swba::apps::write_run_outputs(o, gt, rep);
	const fs::path plots = fs::path(o.out_dir) / "plots";
	for (const char* f : {"ape_window_5", "ape_window_10", "ape_batch", "colormap_window_10", "colormap_batch"})
		for (const char* ext : {".dat", ".gp", ".png", ".svg"})
			EXPECT_TRUE(fs::exists(plots / (std::string(f) + ext))) << f << ext;
	// The colormap is drawn for the rows of the top view only (the largest window, not W=5).
	EXPECT_FALSE(fs::exists(plots / "colormap_window_5.dat"));
	const std::string gp = slurp(plots / "ape_batch.gp");
	for (const char* line : {"title \"rmse (", "title \"median (", "title \"mean (", "filledcurves"})
		EXPECT_NE(gp.find(line), std::string::npos) << line;
	// One colour scale for every colormap: 0 … the largest error of the rows drawn.
	const std::string cm = slurp(plots / "colormap_batch.gp");
	EXPECT_NE(cm.find("set cbrange [0:" + swba::eval::format_significant(rep.rows[2].ape_trans.max, 10) + "]"),
			  std::string::npos)
		<< cm;
	fs::remove_all(o.out_dir);
}
