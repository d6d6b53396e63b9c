// swba run: the plots of the output directory (internal to the run app; see doc/run.md "Output").
#pragma once

#include <swba/apps/run.h>
#include <swba/eval/trajectory.h>

namespace swba::apps
{
/** A row whose APE rmse is at least this many times the best row's is "diverged": drawn clipped. */
constexpr double kDivergedFactor = 10.0;

/** Writes the plots of a run: the top view (the ground truth and the estimates; the estimates alone
 * without ground truth) and, with ground truth, APE rmse vs W, and under plots/ the error over time of
 * every row with APE and the colormap top view of the rows in the top view. Each plot is its .dat and
 * .gp files, rendered to .png/.svg when gnuplot is found. Failed rows are not drawn; diverged rows are drawn
 * clipped (they never set an axis range). Either gets a line in each summary plot and a note in
 * report.notes. Files go to report.files. */
void write_run_plots(const RunOptions& options, const std::vector<mrpt::poses::CPose3D>& ground_truth,
					 RunReport& report);
/** The same with the ground truth as a trajectory (drawn whole; the rows' APE errors already computed). */
void write_run_plots(const RunOptions& options, const eval::Trajectory& ground_truth, RunReport& report);
}  // namespace swba::apps
