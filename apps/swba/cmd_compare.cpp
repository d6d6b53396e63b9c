// swba compare: two sets of swba run results paired by rawlog and estimator (doc/sweeps.md). Logic in
// swba/apps/compare.h.
#include <swba/apps/compare.h>

#include <iostream>

#include "cli.h"
#include "command.h"

namespace swba::app
{
namespace
{
int run_compare(int argc, char** argv)
{
	TCLAP::CmdLine cmd(
		"Compares two sets of swba run results: BASE and OTHER are each a summary.json or a directory searched for "
		"them (swba run --out directories, a sweep of swba jobs, its merge). Rows are paired by rawlog (the path "
		"each summary names) and estimator label; per estimator it prints the geometric means of the figure, "
		"the ratio exp(mean ln(other / base)), the mean log ratio with its standard error, and on how many "
		"rawlogs OTHER is better, worse or the same. Rows without a figure (failed, diverged) and rawlogs on one "
		"side only are counted in notes, not compared.",
		' ', "0.1.0");
	TCLAP::UnlabeledValueArg<std::string> base("BASE", "the reference results", true, "", "BASE", cmd);
	TCLAP::UnlabeledValueArg<std::string> other("OTHER", "the results compared with it", true, "", "OTHER", cmd);
	TCLAP::ValueArg<std::string> metric("", "metric", "figure compared, its rmse (Default: ape_trans)", false,
										"ape_trans", enum_choices<apps::CompareMetric>("|"), cmd);
	TCLAP::SwitchArg per_rawlog("", "per-rawlog", "also print every pair", cmd);
	TCLAP::ValueArg<std::string> json("", "json", "also write the comparison as JSON to FILE", false, "", "FILE", cmd);
	if (auto rc = parse_command_line(cmd, argc, argv)) return *rc;
	const auto parsed_metric = [&metric] {
		try
		{
			return parse_enum<apps::CompareMetric>(metric.getValue(), "metric");
		}
		catch (const std::invalid_argument& e)
		{
			throw UsageError(e.what());
		}
	};
	const apps::CompareOptions o{base.getValue(), other.getValue(), parsed_metric(), per_rawlog.getValue(), json.getValue()};
	return apps::run_compare(o, std::cout, std::cerr);
}
SWBA_REGISTER_COMMAND("compare", "two sets of swba run results paired by rawlog: ratios and their scatter", run_compare);
}  // namespace
}  // namespace swba::app
