/** \file plot.h
 * Headless plots through gnuplot: each plot writes <basename>.dat (data) and <basename>.gp (script)
 * into a directory and, when gnuplot is found, runs it to produce <basename>.png and <basename>.svg.
 * Without gnuplot nothing fails: the result carries a one-line note instead. The .dat and .gp files
 * depend only on the input (numbers with 10 significant digits), so the same input gives the same
 * bytes. The legend is always outside the data (right of the plotting area). */
#pragma once

#include <optional>
#include <string>
#include <utility>
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

/** A closed interval [min, max] of an axis. */
struct AxisRange
{
	double min = 0, max = 0;
};

/** A named x/y series (drawn as a line with points). */
struct PlotSeries
{
	PlotSeries() = default;
	PlotSeries(std::string label_, std::vector<double> x_, std::vector<double> y_, bool clipped_ = false)
		: label(std::move(label_)), x(std::move(x_)), y(std::move(y_)), clipped(clipped_)
	{
	}

	std::string label;
	std::vector<double> x, y;
	/** Drawn, but does not set the axis ranges (a diverged estimator): when any series is clipped,
	 * the script gets explicit ranges from the other series, and gnuplot clips this one at the frame. */
	bool clipped = false;
	/** Optional colour value per point: the line is coloured through the palette (colour bar shown). */
	std::vector<double> color;
	/** gnuplot line properties, e.g. `lc rgb "#808080" dt 2 lw 1`; "" = line type k + 1 (k = index), lw 2. */
	std::string line_style;
};

/** A horizontal reference line at `value`, e.g. the EKF's or the batch solution's rmse. */
struct ReferenceLine
{
	ReferenceLine() = default;
	ReferenceLine(std::string label_, double value_, bool clipped_ = false)
		: label(std::move(label_)), value(value_), clipped(clipped_)
	{
	}

	std::string label;
	double value = 0;
	bool clipped = false;  ///< does not set the y range (see PlotSeries::clipped)
};

/** A horizontal band [low, high] across the x extent of the data (e.g. mean ± std), drawn under the lines. */
struct Band
{
	std::string label;
	double low = 0, high = 0;
};

/** A generic 2-D line plot. */
struct LinePlot
{
	std::string title, xlabel, ylabel;
	std::vector<PlotSeries> series;
	std::vector<ReferenceLine> references;
	std::vector<Band> bands;
	/** One line each, printed under the plot (e.g. "ekf kfEKFNaive: failed at step 7, not drawn"). */
	std::vector<std::string> notes;
	/** Explicit axis ranges; when unset, see plot_ranges(). */
	std::optional<AxisRange> xrange, yrange;
	/** Range of the colour bar (series with `color`); unset = gnuplot's autoscale over the colours. */
	std::optional<AxisRange> color_range;
	std::string color_label;  ///< colour bar title
	bool equal_axes = false;  ///< same scale on x and y (top views)
	bool with_points = true;  ///< mark the data points
};

/** The range of the finite values in `values`, widened by `margin` × its span on each side (a single
 * value v gets ± max(|v|, 1) × margin). nullopt when there is no finite value. */
std::optional<AxisRange> data_range(const std::vector<double>& values, double margin = 0.05);

/** The x and y ranges the script sets explicitly (nullopt = gnuplot autoscales that axis): the
 * plot's own xrange/yrange when given; otherwise, when some series or reference line is clipped,
 * the data_range() of the series, reference lines and bands that are not clipped, so a diverged
 * series never sets the axes; otherwise none. */
std::pair<std::optional<AxisRange>, std::optional<AxisRange>> plot_ranges(const LinePlot& plot);

/** A trajectory with its legend label. */
struct LabelledTrajectory
{
	std::string label;
	Trajectory trajectory;
	bool clipped = false;  ///< drawn, but does not set the axes (see PlotSeries::clipped)
};

/** Full path of the gnuplot executable, or "" if not found (PATH lookup when it has no '/'). */
std::string find_gnuplot(const PlotOptions& options = {});

/** Writes and renders `plot` as <dir>/<basename>.{dat,gp,png,svg}; `dir` is created if missing.
 * Throws std::runtime_error only if the data/script files cannot be written. */
PlotOutput plot_lines(const std::string& dir, const std::string& basename, const LinePlot& plot,
					  const PlotOptions& options = {});

/** The LinePlot of a top view (x–y, equal axes): the reference first, then the estimates. */
LinePlot top_view_plot(const LabelledTrajectory& reference, const std::vector<LabelledTrajectory>& estimates,
					   const std::string& title = "trajectories (top view)");

/** Top view (x–y) of a reference trajectory and one or more estimates, equal axes. */
PlotOutput plot_trajectories_top_view(const std::string& dir, const std::string& basename,
									  const LabelledTrajectory& reference,
									  const std::vector<LabelledTrajectory>& estimates,
									  const std::string& title = "trajectories (top view)",
									  const PlotOptions& options = {});

/** Per-pose errors over time, as evo_ape --plot draws them. */
struct ErrorOverTime
{
	std::string title, label;  ///< plot title; legend label of the error curve
	std::string xlabel = "t (s or step)", ylabel;
	std::vector<double> stamps, errors;  ///< one per pose
	Statistics stats;  ///< of `errors` (rmse, mean, median, std are drawn)
};

/** The error curve with horizontal lines at rmse, mean and median and a band mean ± std (evo's
 * plot). The errors are norms: the y axis is set to 0 … 1.05 × the largest error, so the curve spans
 * at least 95 % of it (autoscaled when every error is 0). */
PlotOutput plot_error_over_time(const std::string& dir, const std::string& basename, const ErrorOverTime& plot,
								const PlotOptions& options = {});

/** The per-pose errors of a result over time (x = stamp), as above. */
PlotOutput plot_error_over_time(const std::string& dir, const std::string& basename, const MetricResult& result,
								const PlotOptions& options = {});

/** Top view of one estimate coloured by its per-pose error (evo's --plot_colormap), over the reference. */
struct ColormapTopView
{
	std::string title;
	LabelledTrajectory reference, estimate;
	std::vector<double> errors;  ///< one per estimate pose
	std::string error_label;	 ///< colour bar title, e.g. "APE translation (m)"
	/** Colour scale; unset = min … max of `errors`. Errors outside it saturate. */
	std::optional<AxisRange> color_range;
	/** The estimate diverged: it is drawn clipped, the reference alone sets the axes. */
	bool clipped = false;
	std::vector<std::string> notes;	 ///< lines printed under the plot
};

/** Throws std::invalid_argument when errors and estimate poses differ in number. */
PlotOutput plot_trajectory_colormap(const std::string& dir, const std::string& basename,
									const ColormapTopView& plot, const PlotOptions& options = {});

/** APE rmse against the window size: one series per estimator configuration (x = window sizes, y =
 * rmse), plus named horizontal reference values (e.g. {"EKF", 0.0161}, {"batch", 0.008}). */
PlotOutput plot_rmse_vs_window(const std::string& dir, const std::string& basename,
							   const std::vector<PlotSeries>& series, const std::vector<ReferenceLine>& references,
							   const std::string& title = "APE rmse vs window size",
							   const std::string& ylabel = "APE translation rmse (m)",
							   const PlotOptions& options = {});
}  // namespace swba::eval
