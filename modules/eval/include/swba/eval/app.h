/** \file app.h
 * The `swba ape` / `swba rpe` commands as functions (the cmd_*.cpp files only parse arguments). */
#pragma once

#include <iosfwd>
#include <string>

#include "swba/eval/evaluation.h"
#include "swba/eval/plot.h"
#include "swba/eval/trajectory.h"

namespace swba::eval
{
/** Reads a trajectory file in `format`: "tum" (read_tum) or "mrpt-gt" (read_mrpt_ground_truth).
 * Throws std::invalid_argument on an unknown format, TrajectoryFileError on a malformed file. */
Trajectory read_trajectory(const std::string& path, const std::string& format = "tum");

/** One `swba ape` / `swba rpe` invocation. */
struct EvaluationCommand
{
	bool relative = false;	///< false: APE (uses `ape`), true: RPE (uses `rpe`)
	std::string ref_path, est_path;
	std::string ref_format = "tum";	 ///< "tum" or "mrpt-gt"
	std::string est_format = "tum";	 ///< "tum" or "mrpt-gt"
	ApeOptions ape;
	RpeOptions rpe;
	std::string save_results_dir;  ///< "" = do not save; else save_results() into it
	std::string plot_dir;		   ///< "" = no plots; else <metric>_trajectories and <metric>_errors
	PlotOptions plot;
};

/** Runs the command: prints evo's text block (format_text_report + a blank line, as evo_ape) to
 * `out`; lists saved files and plot notes (one line each) on `log`. Returns the result. */
MetricResult run_evaluation(const EvaluationCommand& command, std::ostream& out, std::ostream& log);
}  // namespace swba::eval
