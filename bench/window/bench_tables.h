// swba_bench_window's markdown tables (bench_tables.cpp), from the rows bench_window.cpp runs.
#pragma once

#include <swba/apps/run.h>

#include <map>
#include <string>
#include <utility>
#include <vector>

namespace swba::bench
{
/** What one estimator used besides time: its peak resident set and the minor page faults it caused. */
struct Resources
{
	double peak_rss_mib = -1;  ///< −1: unknown (no /proc)
	long minor_faults = 0;
};

/** Label suffix of the rows run with covariance recovery off (--covariance-off). */
inline constexpr const char* kCovarianceOff = " (covariances off)";

/** The markdown tables of one rawlog: ms/step with the APE, the cost per step (`resources` by row
 * label: peak RSS and page faults), the per-tenth cost along the run and, when rows ran with
 * kCovarianceOff, covariances on vs off. */
std::string tables(const apps::RunReport& rep, const std::string& title, const std::map<std::string, Resources>& resources);

/** Per online row of the SLAM-policy window, each run's step times (the main tables' run first). */
using GrowthRuns = std::vector<std::pair<const apps::RunRow*, std::vector<std::vector<double>>>>;

/** The SLAM-policy window's growth along the run over several runs. Per tenth the fastest run's mean (the
 * least disturbed by other load on a shared machine), its last / first, and every run's own last / first. */
std::string growth_table(const GrowthRuns& runs);
}  // namespace swba::bench
