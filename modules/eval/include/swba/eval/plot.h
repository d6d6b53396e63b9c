/** \file plot.h
 * Headless plots through gnuplot: each plot writes <basename>.dat (data) and <basename>.gp (script)
 * into a directory and, when gnuplot is found, runs it to produce <basename>.png and <basename>.svg.
 * Without gnuplot nothing fails: the result carries a one-line note instead. */
#pragma once

#include <string>
#include <vector>

#include "swba/eval/evaluation.h"
#include "swba/eval/trajectory.h"

namespace swba::eval
{
struct PlotOptions
{
	/** gnuplot executable: a name looked up on PATH, or a path. (Default = "gnuplot") */
	std::string gnuplot = "gnuplot";
	int width_px = 800;	  ///< image width, pixels. (Default = 800)
	int height_px = 600;  ///< image height, pixels. (Default = 600)
	bool png = true;	  ///< write <basename>.png. (Default = true)
	bool svg = true;	  ///< write <basename>.svg. (Default = true)
};

/** What a plot call produced. */
struct PlotOutput
{
	bool rendered = false;			 ///< gnuplot ran and produced the images
	std::vector<std::string> files;	 ///< every file written (data, script, images)
	std::string note;				 ///< one line, set when images were not produced (why)
};

/** A named x/y series (drawn as a line with points). */
struct PlotSeries
{
	std::string label;
	std::vector<double> x, y;
};

/** A horizontal reference line at `value`, e.g. the EKF's or the batch solution's rmse. */
struct ReferenceLine
{
	std::string label;
	double value = 0;
};

/** A generic 2-D line plot. */
struct LinePlot
{
	std::string title, xlabel, ylabel;
	std::vector<PlotSeries> series;
	std::vector<ReferenceLine> references;
	bool equal_axes = false;  ///< same scale on x and y (top views)
	bool with_points = true;  ///< mark the data points
};

/** A trajectory with its legend label. */
struct LabelledTrajectory
{
	std::string label;
	Trajectory trajectory;
};

/** Full path of the gnuplot executable, or "" if not found (PATH lookup when it has no '/'). */
std::string find_gnuplot(const PlotOptions& options = {});

/** Writes and renders `plot` as <dir>/<basename>.{dat,gp,png,svg}; `dir` is created if missing.
 * Throws std::runtime_error only if the data/script files cannot be written. */
PlotOutput plot_lines(const std::string& dir, const std::string& basename, const LinePlot& plot,
					  const PlotOptions& options = {});

/** Top view (x–y) of a reference trajectory and one or more estimates, equal axes. */
PlotOutput plot_trajectories_top_view(const std::string& dir, const std::string& basename,
									  const LabelledTrajectory& reference,
									  const std::vector<LabelledTrajectory>& estimates,
									  const std::string& title = "trajectories (top view)",
									  const PlotOptions& options = {});

/** The per-pose errors of a result over time (x = stamp), with its rmse as a reference line. */
PlotOutput plot_error_over_time(const std::string& dir, const std::string& basename, const MetricResult& result,
								const PlotOptions& options = {});

/** APE rmse against the window size: one series per estimator configuration (x = window sizes, y =
 * rmse), plus named horizontal reference values (e.g. {"EKF", 0.0161}, {"batch", 0.008}). */
PlotOutput plot_rmse_vs_window(const std::string& dir, const std::string& basename,
							   const std::vector<PlotSeries>& series, const std::vector<ReferenceLine>& references,
							   const std::string& title = "APE rmse vs window size",
							   const std::string& ylabel = "APE translation rmse (m)",
							   const PlotOptions& options = {});
}  // namespace swba::eval
