#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <iostream>

#include "window_test_utils.h"

using namespace swba;
using namespace swba::estimators;

TEST(WindowScratch, Debug)
{
	if (!std::getenv("SWBA_SCRATCH")) GTEST_SKIP();
	auto rawlog = io::read_rawlog(test::dataset("kf-slam_6D_demo.rawlog"));
	rawlog.steps.resize(40);
	for (auto gauge : {GaugeMode::Fixed, GaugeMode::Free})
		for (bool fej : {true, false})
		{
			SlidingWindowOptions opt;
			opt.window_size = 8;
			opt.gauge = gauge;
			opt.first_estimate_jacobians = fej;
			SlidingWindowEstimator est(opt);
			try
			{
				for (const auto& s : rawlog.steps)
				{
					const auto& r = est.process(s);
					if (std::getenv("SWBA_VERBOSE"))
						std::cout << r.step << " it " << r.iterations << " cost " << r.initial_cost << " -> " << r.final_cost
								  << " lm " << r.landmarks << " prior " << r.prior_rank << "/" << r.prior_variables
								  << " reanch " << r.reanchored << "\n";
				}
				std::cout << to_string(gauge) << " fej " << fej << " ok\n";
			}
			catch (const std::exception& e)
			{
				std::cout << to_string(gauge) << " fej " << fej << " FAIL " << e.what() << "\n";
			}
		}
}
