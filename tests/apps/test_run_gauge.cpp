// swba run under the free gauge: every row is reported in the frame the fixed gauge holds (the
// estimate relative to its own estimate of the initial pose), so its APE compares with the others.
#include <swba/apps/run.h>
#include <swba/eval/ground_truth.h>
#include <swba/io/rawlog.h>

#include <gtest/gtest.h>

#include <sstream>

namespace
{
swba::apps::RunReport run(swba::GaugeMode gauge, const swba::io::Rawlog& rawlog,
						  const std::vector<mrpt::poses::CPose3D>& gt)
{
	swba::apps::RunOptions o;
	o.windows = {10};
	o.run_ekf = false;
	o.progress = false;
	o.window.gauge = gauge;
	std::ostringstream log;
	return swba::apps::run_estimators(o, rawlog, gt, log);
}
}  // namespace

TEST(RunGauge, FreeGaugeRowsAreInTheFixedGaugesFrame)
{
	const std::string path = std::string(SWBA_MRPT_DATASETS) + "/kf-slam_6D_demo.rawlog";
	swba::io::RawlogReaderOptions ro;
	ro.max_steps = 150;
	const swba::io::Rawlog rawlog = swba::io::read_rawlog(path, ro);
	const auto gt = swba::eval::read_ground_truth_for(swba::eval::default_ground_truth_path(path), rawlog.steps.size());
	const auto fixed = run(swba::GaugeMode::Fixed, rawlog, gt), free = run(swba::GaugeMode::Free, rawlog, gt);
	ASSERT_EQ(fixed.rows.size(), 4u);  // window online, lagged, batch from two starts
	ASSERT_EQ(free.rows.size(), 4u);
	for (std::size_t i = 0; i < 4; i++)
	{
		ASSERT_TRUE(fixed.rows[i].has_ape && free.rows[i].has_ape) << fixed.rows[i].label;
		const double f = fixed.rows[i].ape_trans.rmse, g = free.rows[i].ape_trans.rmse;
		std::cout << "[run gauge] " << fixed.rows[i].label << ": unaligned APE fixed " << f << ", free " << g << "\n";
		// Batch reaches the same optimum up to the gauge: equal once expressed in the same frame.
		EXPECT_NEAR(g, f, (fixed.rows[i].name.rfind("batch", 0) == 0 ? 1e-3 : 0.1) * f) << fixed.rows[i].label;
	}
}
