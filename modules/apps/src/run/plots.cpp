// swba run: top view, APE rmse vs W, error over time and colormap top views, with failed rows left
// out and diverged rows clipped.
#include "plots.h"

#include <swba/eval/ground_truth.h>
#include <swba/eval/plot.h>
#include <swba/eval/text_format.h>

#include <mrpt/system/filesystem.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>

namespace swba::apps
{
namespace
{
/** How the rows enter the plots: which failed, which diverged, and the lines that say so. */
struct RowTriage
{
	const RunRow* best = nullptr;  ///< the row with APE of lowest translation rmse
	std::vector<const RunRow*> diverged;
	std::vector<std::string> failed_lines;  ///< "<label>: failed at step k, not drawn"

	bool is_diverged(const RunRow& r) const
	{
		return std::find(diverged.begin(), diverged.end(), &r) != diverged.end();
	}
	/** The line naming a diverged row (in the plots and on stderr). */
	std::string diverged_line(const RunRow& r) const
	{
		return r.label + ": diverged (APE rmse " + eval::format_significant(r.ape_trans.rmse, 4) + " m, " +
			   eval::format_significant(r.ape_trans.rmse / best->ape_trans.rmse, 3) + "x the best, " + best->label +
			   "), drawn clipped";
	}
	/** The lines of a summary plot: every failed row, and the diverged rows among `shown`. */
	std::vector<std::string> plot_lines(const std::vector<const RunRow*>& shown) const
	{
		std::vector<std::string> lines = failed_lines;
		for (const RunRow* r : shown)
			if (is_diverged(*r)) lines.push_back(diverged_line(*r));
		return lines;
	}
};

RowTriage triage_rows(const RunReport& report)
{
	RowTriage t;
	for (const auto& r : report.rows)
	{
		if (r.failed) t.failed_lines.push_back(r.label + ": failed at step " + std::to_string(r.failed_step) + ", not drawn");
		if (r.has_ape && std::isfinite(r.ape_trans.rmse) && (!t.best || r.ape_trans.rmse < t.best->ape_trans.rmse))
			t.best = &r;
	}
	for (const auto& r : report.rows)
		if (r.has_ape && t.best && !(r.ape_trans.rmse < kDivergedFactor * t.best->ape_trans.rmse)) t.diverged.push_back(&r);
	return t;
}

/** Records a plot's files; its note only when gnuplot is there but failed (a missing gnuplot is said
 * once for the whole run, by write_run_outputs). */
void add_plot_files(const eval::PlotOutput& o, RunReport& report)
{
	for (const auto& f : o.files) report.files.push_back(f);
	if (!o.note.empty() && !eval::find_gnuplot().empty()) report.notes.push_back(o.note);
}

/** The rows of the top views: each EKF, the largest window (online), batch and causal; no failed row. */
std::vector<const RunRow*> top_view_rows(const RunReport& report)
{
	const RunRow* widest = nullptr;
	for (const auto& r : report.rows)
		if (r.name == "window" && r.trajectory == "online" && !r.failed && (!widest || r.window > widest->window))
			widest = &r;
	std::vector<const RunRow*> shown;
	for (const auto& r : report.rows)
		if (!r.failed && !r.estimate.empty() &&
			(r.name == "ekf" || r.name == "eskf" || r.name == "batch" || r.name == "causal" || &r == widest))
			shown.push_back(&r);
	return shown;
}

std::string rawlog_name(const RunReport& report) { return mrpt::system::extractFileName(report.rawlog); }

void plot_top_view(const std::string& dir, const eval::Trajectory& gt, const RowTriage& triage, RunReport& report,
				   const eval::PlotOptions& po)
{
	const auto shown = top_view_rows(report);
	std::vector<eval::LabelledTrajectory> estimates;
	for (const RunRow* r : shown)
		estimates.push_back({r->label + (triage.is_diverged(*r) ? " (diverged)" : ""), r->estimate, triage.is_diverged(*r)});
	const std::string title = "trajectories (top view): " + rawlog_name(report);
	eval::LinePlot p;
	if (!gt.empty())
		p = eval::top_view_plot({"ground truth", gt}, estimates, title);
	else if (!estimates.empty())  // no ground truth: the estimates alone, the first one in the reference's place
		p = eval::top_view_plot(estimates.front(), {estimates.begin() + 1, estimates.end()}, title);
	else
		return;
	p.notes = triage.plot_lines(shown);
	add_plot_files(eval::plot_lines(dir, "trajectories", p, po), report);
}

/** APE rmse vs W: one series per (online/lagged × policy × FEJ); EKF, batch, causal as reference
 * lines. With a diverged row the y range is set from the other rows' rmse only. */
void plot_ape_vs_window(const RunOptions& options, const RowTriage& triage, RunReport& report,
						const eval::PlotOptions& po)
{
	eval::LinePlot p;
	p.title = "APE rmse vs window size: " + rawlog_name(report);
	p.xlabel = "window size (poses)";
	p.ylabel = "APE translation rmse (m)";
	std::map<std::string, std::size_t> series_of;
	std::vector<const RunRow*> shown;
	std::vector<double> kept;  // the rmse values that set the y range
	for (const auto& r : report.rows)
	{
		if (!r.has_ape) continue;
		shown.push_back(&r);
		const bool diverged = triage.is_diverged(r);
		if (!diverged) kept.push_back(r.ape_trans.rmse);
		if (r.name != "window")
		{
			p.references.push_back({r.label + (diverged ? " (diverged)" : ""), r.ape_trans.rmse, diverged});
			continue;
		}
		std::string key = "window " + r.trajectory;
		if (options.policies.size() * options.fej.size() > 1)
			key += std::string(" ") + r.policy + " " + (r.fej && *r.fej ? "fej" : "nofej");
		if (!series_of.count(key))
		{
			series_of[key] = p.series.size();
			p.series.push_back({key, {}, {}});
		}
		auto& s = p.series[series_of[key]];
		s.x.push_back(r.window);
		s.y.push_back(r.ape_trans.rmse);
	}
	if (p.series.empty()) return;
	if (!triage.diverged.empty()) p.yrange = eval::data_range(kept);
	// Explicit also so that a single W gets a range (gnuplot warns on an empty one) and no point sits on the frame.
	std::vector<double> windows;
	for (const auto& s : p.series) windows.insert(windows.end(), s.x.begin(), s.x.end());
	p.xrange = eval::data_range(windows);
	p.notes = triage.plot_lines(shown);
	add_plot_files(eval::plot_lines(options.out_dir, "ape_rmse_vs_window", p, po), report);
}

/** The name of a row's plots: its TUM file's stem, or its label made file-safe. */
std::string plot_stem(const RunRow& r)
{
	std::string stem = r.file.size() > 4 ? r.file.substr(0, r.file.size() - 4) : r.label;
	for (auto& c : stem)
		if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.')) c = '_';
	return stem;
}

/** plots/ape_<stem>: the row's APE translation error over time, with rmse/mean/median and ± std. */
void plot_row_errors(const std::string& dir, const RunRow& r, const RowTriage& triage, RunReport& report,
					 const eval::PlotOptions& po)
{
	eval::ErrorOverTime e;
	e.title = "APE w.r.t. translation part (not aligned): " + r.label + (triage.is_diverged(r) ? " (diverged)" : "");
	e.label = "APE translation";
	e.xlabel = report.time_label;
	e.ylabel = "APE translation (m)";
	e.stamps = r.estimate.stamps;
	e.errors = r.ape_trans_errors;
	e.stats = r.ape_trans;
	add_plot_files(eval::plot_error_over_time(dir, "ape_" + plot_stem(r), e, po), report);
}

/** plots/colormap_<stem> for the rows of the top view, on one colour scale 0 … the largest error of
 * the non-diverged ones (so the colours compare between the plots; a diverged row saturates). */
void plot_colormaps(const std::string& dir, const eval::Trajectory& gt, const RowTriage& triage,
					RunReport& report, const eval::PlotOptions& po)
{
	std::vector<const RunRow*> rows;
	double top = 0;
	for (const RunRow* r : top_view_rows(report))
		if (r->has_ape && r->ape_trans_errors.size() == r->estimate.size())
		{
			rows.push_back(r);
			if (!triage.is_diverged(*r)) top = std::max(top, r->ape_trans.max);
		}
	for (const RunRow* r : rows)
	{
		eval::ColormapTopView c;
		c.title = "APE translation along the path: " + r->label + " (" + rawlog_name(report) + ")";
		c.reference = {"ground truth", gt};
		c.estimate = {r->label, r->estimate};
		c.errors = r->ape_trans_errors;
		c.error_label = "APE translation (m)";
		if (top > 0) c.color_range = eval::AxisRange{0, top};
		c.clipped = triage.is_diverged(*r);
		if (c.clipped) c.notes.push_back(triage.diverged_line(*r) + "; colours saturate");
		add_plot_files(eval::plot_trajectory_colormap(dir, "colormap_" + plot_stem(*r), c, po), report);
	}
}
}  // namespace

void write_run_plots(const RunOptions& options, const std::vector<mrpt::poses::CPose3D>& ground_truth,
					 RunReport& report)
{
	// Rows 0 … steps, as gt.tum: a --max-steps run does not draw the rest of the ground truth.
	const std::vector<mrpt::poses::CPose3D> used(
		ground_truth.begin(),
		ground_truth.begin() + static_cast<std::ptrdiff_t>(std::min(ground_truth.size(), report.steps + 1)));
	write_run_plots(options, eval::ground_truth_trajectory(used), report);
}

void write_run_plots(const RunOptions& options, const eval::Trajectory& gt, RunReport& report)
{
	eval::PlotOptions po;
	const RowTriage triage = triage_rows(report);
	for (const auto& line : triage.failed_lines) report.notes.push_back(line);
	for (const RunRow* r : triage.diverged) report.notes.push_back(triage.diverged_line(*r));
	plot_top_view(options.out_dir, gt, triage, report, po);
	plot_ape_vs_window(options, triage, report, po);
	const std::string per_row = options.out_dir + "/plots";
	for (const auto& r : report.rows)
		if (r.has_ape && r.ape_trans_errors.size() == r.estimate.size()) plot_row_errors(per_row, r, triage, report, po);
	plot_colormaps(per_row, gt, triage, report, po);
}
}  // namespace swba::apps
