// swba nees / swba merge of a NEES sweep: the average NEES table, nees.csv and plots (see nees.h).
#include "../report_helpers.h"
#include "summary_json.h"

#include <swba/apps/nees.h>
#include <swba/core/file.h>
#include <swba/eval/ground_truth.h>
#include <swba/eval/plot.h>

#include <swba/eval/text_format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <ostream>
#include <sstream>
#include <stdexcept>

namespace swba::apps
{
namespace fs = std::filesystem;

using detail::fixed;
using detail::pad_left;
using detail::pad_right;

namespace
{
std::string exact(double v)
{
	char buf[40];
	std::snprintf(buf, sizeof(buf), "%.17g", v);
	return buf;
}

/** "3" when every step has dof_sum / runs = d, else "varies". */
std::string dof_text(const eval::AverageNeesSeries& s, const std::vector<std::size_t>& runs)
{
	if (s.dof_sum.empty()) return "-";
	std::set<double> dofs;
	for (std::size_t k = 0; k < s.dof_sum.size(); k++) dofs.insert(static_cast<double>(s.dof_sum[k]) / static_cast<double>(runs[k]));
	if (dofs.size() != 1) return "varies";
	const double d = *dofs.begin();
	return d == std::floor(d) ? std::to_string(static_cast<int>(d)) : fixed(d, 2);
}

std::string band_text(const eval::AverageNeesSeries& s)
{
	if (s.band.empty()) return "-";
	for (const auto& b : s.band)
		if (b.low != s.band.front().low || b.high != s.band.front().high) return "varies";
	return "[" + fixed(s.band.front().low, 2) + ", " + fixed(s.band.front().high, 2) + "]";
}

std::string seeds_text(const std::vector<long>& seeds)
{
	if (seeds.empty()) return "";
	bool consecutive = true;
	for (std::size_t i = 1; i < seeds.size(); i++) consecutive = consecutive && seeds[i] == seeds[i - 1] + 1;
	if (consecutive) return std::to_string(seeds.front()) + (seeds.size() > 1 ? "-" + std::to_string(seeds.back()) : "");
	std::string s;
	for (long x : seeds) s += (s.empty() ? "" : ",") + std::to_string(x);
	return s;
}

/** nees_<quantity>: the average NEES of every estimator vs step, with the band. */
void plot_quantity(const std::string& dir, const NeesReport& report, bool position, std::vector<std::string>& files)
{
	eval::LinePlot p;
	const std::string what = position ? "position" : "pose";
	p.title = "average " + what + " NEES over " + std::to_string(report.seeds.size()) + " runs (no alignment)";
	p.xlabel = "t = step k + 1";
	p.ylabel = "average " + what + " NEES";
	p.with_points = false;
	std::vector<double> kept;
	for (const auto& e : report.estimators)
	{
		const auto& s = position ? e.average.position : e.average.pose;
		if (s.mean.empty()) continue;
		p.series.push_back({e.label, e.average.stamps, s.mean});
		kept.insert(kept.end(), s.mean.begin(), s.mean.end());
	}
	if (p.series.empty()) return;
	// The band of the first estimator (every estimator has the same runs and dof unless one failed).
	const auto& first = position ? report.estimators.front().average.position : report.estimators.front().average.pose;
	if (band_text(first) != "varies" && !first.band.empty())
		p.bands.push_back({"95% band (" + std::to_string(report.estimators.front().average.runs.front()) + " runs, " +
							   dof_text(first, report.estimators.front().average.runs) + " dof)",
						   first.band.front().low, first.band.front().high});
	else
	{
		std::vector<double> lo, hi;
		for (const auto& b : first.band)
		{
			lo.push_back(b.low);
			hi.push_back(b.high);
		}
		eval::PlotSeries l("95% band low", report.estimators.front().average.stamps, lo);
		eval::PlotSeries h("95% band high", report.estimators.front().average.stamps, hi);
		l.line_style = h.line_style = "lc rgb \"#808080\" dt 2 lw 1";
		p.series.push_back(l);
		p.series.push_back(h);
	}
	const auto out = eval::plot_lines(dir, "nees_" + what, p);
	files.insert(files.end(), out.files.begin(), out.files.end());
}
/** Each estimator's NEES runs over the sweep's jobs, by label. */
using NeesRunsByLabel = std::map<std::string, std::vector<eval::RunNees>>;

/** One job's rows: each estimator's NEES run against the job's ground truth, or its failure (estimators
 * enter `report` in the order first seen, `index` maps their labels there). */
void add_job_nees(const JobSummary& s, long seed, NeesReport& report, std::map<std::string, std::size_t>& index,
				  NeesRunsByLabel& runs)
{
	if (report.steps == 0) report.steps = s.json.at("steps").get<std::size_t>();
	if (s.json.at("ground_truth").is_null()) throw std::runtime_error(s.path + ": the run had no ground truth: no NEES");
	const std::string gt_path = s.json.at("ground_truth").get<std::string>();
	const auto gt = eval::read_ground_truth_for(gt_path, s.json.at("steps").get<std::size_t>());
	for (const auto& e : s.json.at("estimators"))
	{
		const RunRow row = run_row_from_json(e, s.dir, s.path);
		if (!index.count(row.label))
		{
			index[row.label] = report.estimators.size();
			report.estimators.push_back({row.label, 0, {}, 0, {}});
		}
		NeesEstimator& est = report.estimators[index[row.label]];
		if (row.failed)
		{
			est.failures.push_back("seed " + std::to_string(seed) + ": failed at step " +
								   std::to_string(row.failed_step) + ": " + row.failure);
			continue;
		}
		if (row.file.empty()) throw std::runtime_error(s.path + ": " + row.label + " has no trajectory file");
		const std::string cov = find_covariance_file(s.dir, row);
		if (cov.empty())
			throw std::runtime_error("no covariance file " + s.dir + "/" + covariance_file_name(row.file) +
									 ": swba run writes <stem>.cov next to each TUM file (doc/sweeps.md); this "
									 "job's run wrote none, so there is no NEES");
		runs[row.label].push_back(eval::run_nees(row.estimate, eval::read_covariance_file(cov), gt, cov));
		est.fixed_poses += runs[row.label].back().fixed_poses;
		est.runs++;
	}
}

/** nees.txt, nees.csv and (with gnuplot) the plots into `dir`; returns the table. */
std::string write_nees_files(const std::string& dir, const MergeOptions& options, NeesReport& report, std::ostream& log)
{
	std::error_code ec;
	fs::create_directories(dir, ec);
	if (ec) throw std::runtime_error("cannot create '" + dir + "': " + ec.message());
	const std::string table = format_nees_table(report);
	for (const auto& [name, text] : {std::make_pair("nees.txt", table), std::make_pair("nees.csv", format_nees_csv(report))})
	{
		write_text_file_atomically(dir + "/" + name, text);
		report.files.push_back(dir + "/" + name);
	}
	if (options.plots)
	{
		if (eval::find_gnuplot().empty())
			log << "note: gnuplot not found: no plots\n";
		else
			for (const bool position : {true, false}) plot_quantity(dir, report, position, report.files);
	}
	return table;
}
}  // namespace

NeesReport merge_nees_sweep(const SweepPlan& plan, const MergeOptions& options, std::ostream& out, std::ostream& log)
{
	const std::vector<JobSummary> summaries = check_mergeable(plan, SweepKind::Nees, "NEES", log);
	NeesReport report;
	report.simulate_ini = plan.simulate_ini;
	NeesRunsByLabel runs;
	std::map<std::string, std::size_t> index;
	for (const auto& g : plan.groups)
	{
		report.seeds.push_back(g.seed);
		for (std::size_t id : g.jobs) add_job_nees(summaries[id - 1], g.seed, report, index, runs);
	}
	for (auto& e : report.estimators)
	{
		e.average = eval::average_nees(runs[e.label]);
		for (const auto& f : e.failures) log << options.program << ": " << e.label << ": " << f << ": left out of the average\n";
	}
	const std::string dir = options.out_dir.empty() ? plan.dir + "/nees" : options.out_dir;
	const std::string table = write_nees_files(dir, options, report, log);
	out << table << std::flush;
	detail::print_wrote_files(log, options.program, report.files.size(), dir);
	return report;
}

std::string format_nees_table(const NeesReport& r)
{
	std::size_t wl = std::string("estimator").size();
	for (const auto& e : r.estimators) wl = std::max(wl, e.label.size());
	std::ostringstream s;
	s << "swba nees: " << r.seeds.size() << " runs (seeds " << seeds_text(r.seeds) << ") of "
	  << fs::path(r.simulate_ini).filename().string() << ", " << r.steps << " steps\n"
	  << "average NEES over the runs at each step vs the 95% chi-square band of that average; not aligned (the\n"
	  << "estimate and the ground truth share the first pose); 'in band' = share of steps inside it\n";
	const std::string group = pad_left("dof", 5) + pad_left("band", 15) + pad_left("in band", 9) + pad_left("mean", 9);
	s << pad_right("", wl + 6) << pad_right(" position NEES", group.size()) << " pose NEES\n";
	s << pad_right("estimator", wl) << pad_left("runs", 6) << group << group << "\n";
	s << std::string(wl + 6 + 2 * group.size(), '-') << "\n";
	for (const auto& e : r.estimators)
	{
		s << pad_right(e.label, wl) << pad_left(std::to_string(e.runs), 6);
		for (const auto* q : {&e.average.position, &e.average.pose})
		{
			if (q->mean.empty())
			{
				s << pad_left("-", 5) << pad_left("-", 15) << pad_left("-", 9) << pad_left("-", 9);
				continue;
			}
			s << pad_left(dof_text(*q, e.average.runs), 5) << pad_left(band_text(*q), 15)
			  << pad_left(fixed(100 * q->share_in_band, 1) + " %", 9) << pad_left(fixed(q->mean_over_steps, 3), 9);
		}
		if (!e.failures.empty()) s << "  (" << e.failures.size() << " runs failed, left out)";
		s << "\n";
	}
	for (const auto& e : r.estimators)
		if (e.fixed_poses)
			s << "note: " << e.label << ": " << e.fixed_poses
			  << " poses with a zero covariance (every dof fixed, e.g. before the filter's first prediction) left out\n";
	for (const auto& e : r.estimators)
	{
		const std::string p = dof_text(e.average.position, e.average.runs), q = dof_text(e.average.pose, e.average.runs);
		if ((p != "3" && p != "-") || (q != "6" && q != "-"))
			s << "note: " << e.label << ": fixed dofs (zero rows and columns of its covariance, e.g. a planar model) "
			  << "left out: position NEES over " << p << " dof, pose NEES over " << q << " dof\n";
	}
	return s.str();
}

std::string format_nees_csv(const NeesReport& r)
{
	std::ostringstream s;
	// *_dof_sum: N·d over the step's N runs, the degrees of freedom of the band's χ² (not one pose's d).
	s << "label,stamp,runs,position_nees,position_dof_sum,position_band_low,position_band_high,pose_nees,pose_dof_sum,"
		 "pose_band_low,pose_band_high\n";
	for (const auto& e : r.estimators)
	{
		const auto& a = e.average;
		for (std::size_t k = 0; k < a.stamps.size(); k++)
			s << eval::csv_field(e.label) << "," << exact(a.stamps[k]) << "," << a.runs[k] << ","
			  << exact(a.position.mean[k]) << "," << a.position.dof_sum[k] << "," << exact(a.position.band[k].low)
			  << "," << exact(a.position.band[k].high) << "," << exact(a.pose.mean[k]) << "," << a.pose.dof_sum[k]
			  << "," << exact(a.pose.band[k].low) << "," << exact(a.pose.band[k].high) << "\n";
	}
	return s.str();
}
}  // namespace swba::apps
