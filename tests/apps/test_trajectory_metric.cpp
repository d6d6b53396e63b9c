// swba ape / rpe as a library call: prints evo's text block and saves the result files.
#include <gtest/gtest.h>
#include <swba/apps/trajectory_metric.h>
#include <swba/eval/report.h>

#include <filesystem>
#include <sstream>

using namespace swba::apps;
using namespace swba::eval;
namespace fs = std::filesystem;

namespace
{
std::string metric_dir(const std::string& name)
{
	const fs::path p = fs::temp_directory_path() / ("swba_test_trajectory_metric_" + name);
	fs::remove_all(p);
	return p.string();
}
}  // namespace

TEST(App, RunEvaluationPrintsTheTextBlockAndSaves)
{
	const std::string dir = metric_dir("app");
	TrajectoryMetricOptions c;
	c.ref_path = std::string(SWBA_DATA_DIR) + "/evo_reference/gt_kf-slam_6D_demo.tum";
	c.est_path = std::string(SWBA_DATA_DIR) + "/evo_reference/ekf_kf-slam_6D_demo.tum";
	c.ape.alignment.align = true;
	c.save_results_dir = dir;
	std::ostringstream out, log;
	const MetricResult r = run_trajectory_metric(c, out, log);
	EXPECT_EQ(out.str(), format_text_report(r) + "\n");
	EXPECT_NE(log.str().find("ape_stats.json"), std::string::npos);
	EXPECT_THROW((void)swba::parse_enum<TrajectoryFormat>("kitti", "trajectory format"), std::invalid_argument);
	// Association keeps a subset of the reference poses.
	EXPECT_GE(read_trajectory(c.ref_path, TrajectoryFormat::Tum).size(), r.ref.size());
	fs::remove_all(dir);
}
