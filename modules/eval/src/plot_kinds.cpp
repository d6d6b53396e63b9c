// The plots built on plot_lines: top views (plain and coloured by error), error over time, rmse vs W.
#include "swba/eval/plot.h"
#include "swba/eval/text_format.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace swba::eval
{
namespace
{
PlotSeries xy_series(const LabelledTrajectory& t)
{
	PlotSeries s;
	s.label = t.label;
	s.clipped = t.clipped;
	for (const auto& pose : t.trajectory.poses)
	{
		s.x.push_back(pose.x());
		s.y.push_back(pose.y());
	}
	return s;
}
}  // namespace

LinePlot top_view_plot(const LabelledTrajectory& reference, const std::vector<LabelledTrajectory>& estimates,
					   const std::string& title)
{
	LinePlot p;
	p.title = title;
	p.xlabel = "x (m)";
	p.ylabel = "y (m)";
	p.equal_axes = true;
	p.with_points = false;
	p.series.push_back(xy_series(reference));
	for (const auto& e : estimates) p.series.push_back(xy_series(e));
	return p;
}

PlotOutput plot_trajectories_top_view(const std::string& dir, const std::string& basename,
									  const LabelledTrajectory& reference,
									  const std::vector<LabelledTrajectory>& estimates, const std::string& title,
									  const PlotOptions& options)
{
	return plot_lines(dir, basename, top_view_plot(reference, estimates, title), options);
}

PlotOutput plot_error_over_time(const std::string& dir, const std::string& basename, const ErrorOverTime& e,
								const PlotOptions& options)
{
	LinePlot p;
	p.title = e.title;
	p.xlabel = e.xlabel;
	p.ylabel = e.ylabel;
	p.with_points = false;
	p.series.push_back({e.label, e.stamps, e.errors});
	p.series.back().line_style = "lw 1 lt 1";  // thin: thousands of poses must not hide the lines drawn over them
	// The errors are norms (≥ 0): the y axis runs from 0 to just above the largest, so the curve fills
	// the plot and every statistic drawn (each ≤ the maximum) is inside it.
	double top = 0;
	for (double v : e.errors)
		if (std::isfinite(v)) top = std::max(top, v);
	if (top > 0) p.yrange = AxisRange{0, top * 1.05};
	// evo's order and meaning: rmse, median, mean as horizontal lines, the band mean ± std under them.
	p.references.push_back({"rmse", e.stats.rmse});
	p.references.push_back({"median", e.stats.median});
	p.references.push_back({"mean", e.stats.mean});
	p.bands.push_back(
		{"mean ± std (std " + format_significant(e.stats.std, 6) + ")", e.stats.mean - e.stats.std,
		 e.stats.mean + e.stats.std});
	return plot_lines(dir, basename, p, options);
}

PlotOutput plot_error_over_time(const std::string& dir, const std::string& basename, const MetricResult& result,
								const PlotOptions& options)
{
	ErrorOverTime e;
	e.title = result.title;
	e.label = result.metric + " " + pose_relation_name(result.relation);
	e.ylabel = result.metric + " (" + result.unit + ")";
	e.stamps = result.stamps;
	e.errors = result.errors;
	e.stats = result.stats;
	return plot_error_over_time(dir, basename, e, options);
}

PlotOutput plot_trajectory_colormap(const std::string& dir, const std::string& basename, const ColormapTopView& c,
									const PlotOptions& options)
{
	if (c.errors.size() != c.estimate.trajectory.size())
		throw std::invalid_argument("plot_trajectory_colormap: " + std::to_string(c.errors.size()) + " errors for " +
									std::to_string(c.estimate.trajectory.size()) + " poses of " + c.estimate.label);
	LabelledTrajectory est = c.estimate;
	est.clipped = c.clipped;
	LinePlot p = top_view_plot(c.reference, {est}, c.title);
	p.series.front().line_style = "lc rgb \"#808080\" dt 2 lw 1";  // as evo: the reference grey and dashed
	p.series.back().color = c.errors;
	p.color_label = c.error_label;
	p.color_range = c.color_range;
	p.notes = c.notes;
	return plot_lines(dir, basename, p, options);
}

PlotOutput plot_rmse_vs_window(const std::string& dir, const std::string& basename,
							   const std::vector<PlotSeries>& series, const std::vector<ReferenceLine>& references,
							   const std::string& title, const std::string& ylabel, const PlotOptions& options)
{
	LinePlot p;
	p.title = title;
	p.xlabel = "window size (poses)";
	p.ylabel = ylabel;
	p.series = series;
	p.references = references;
	p.with_points = true;
	return plot_lines(dir, basename, p, options);
}
}  // namespace swba::eval
