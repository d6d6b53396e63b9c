/** \file trajectory_metric.h
 * `swba ape` / `swba rpe`: one trajectory against a reference, evo's definitions and text output. */
#pragma once

#include <iosfwd>
#include <string>

#include <swba/eval/evaluation.h>
#include <swba/eval/plot.h>
#include <swba/eval/trajectory.h>

namespace swba::apps
{
/** One `swba ape` / `swba rpe` invocation. */
struct TrajectoryMetricOptions
{
	bool relative = false;	///< false: APE (uses `ape`), true: RPE (uses `rpe`)
	std::string ref_path, est_path;
	eval::TrajectoryFormat ref_format = eval::TrajectoryFormat::Tum;
	eval::TrajectoryFormat est_format = eval::TrajectoryFormat::Tum;
	eval::ApeOptions ape;
	eval::RpeOptions rpe;
	std::string save_results_dir;  ///< "" = do not save; else save_results() into it
	std::string plot_dir;		   ///< "" = no plots; else <metric>_trajectories and <metric>_errors
	eval::PlotOptions plot;
};

/** Runs the command: prints evo's text block (format_text_report + a blank line, as evo_ape) to
 * `out`; lists saved files and plot notes (one line each) on `log`. Returns the result. */
eval::MetricResult run_trajectory_metric(const TrajectoryMetricOptions& options, std::ostream& out, std::ostream& log);
}  // namespace swba::apps
