// swba_bench_window's markdown tables: ms/step with the APE, the cost per step, the per-tenth cost
// along the run, its growth over several runs and covariance recovery on vs off (bench_window.cpp runs).
#include "bench_tables.h"

#include <swba/eval/text_format.h>
#include <swba/linear/rank_update.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

namespace swba::bench
{
using apps::RunReport;
using apps::RunRow;

namespace
{
/** A table cell: `v` by the printf conversion `f`. */
std::string fmt(const char* f, double v) { return swba::eval::format_printf(f, v); }

/** The q-quantile (0..1) of v (nearest rank), 0 for an empty v. */
double quantile_of(std::vector<double> v, double q)
{
	if (v.empty()) return 0;
	std::sort(v.begin(), v.end());
	const auto i = static_cast<std::size_t>(std::ceil(q * double(v.size()))) - (q > 0 ? 1 : 0);
	return v[std::min(i, v.size() - 1)];
}

/** Mean of v over [b, e). */
double mean_of(const std::vector<double>& v, std::size_t b, std::size_t e)
{
	if (e <= b) return 0;
	return std::accumulate(v.begin() + std::ptrdiff_t(b), v.begin() + std::ptrdiff_t(e), 0.0) / double(e - b);
}

std::string row_name(const RunRow& r)
{
	if (r.name == "window")
	{
		const auto prefix = r.label.find(" (first ");
		return "window " + r.policy + (prefix == std::string::npos ? "" : r.label.substr(prefix));
	}
	return r.label;
}

/** The W column: the window size, or a dash for rows without one. */
std::string window_cell(const RunRow& r) { return r.window ? std::to_string(r.window) : "–"; }

/** The last seven cells of a timing-table row: where a window's time went (LM solve vs
 * marginalisation) and its state size, means over the steps; dashes for rows without step summaries. */
std::string step_summary_cells(const RunRow& r)
{
	if (r.step_summaries.empty()) return "– | – | – | – | – | – | – |\n";
	double solve = 0, marg = 0, lms = 0, in_solve = 0;
	for (const auto& st : r.step_summaries)
	{
		solve += st.solve_seconds;
		marg += st.marginalization_seconds;
		lms += st.landmarks;
		in_solve += st.landmarks - st.prior_only_landmarks;
	}
	const double n = double(r.step_summaries.size());
	const auto& last = r.step_summaries.back();
	std::ostringstream s;
	s << fmt("%.2f", solve * 1e3 / n) << " | " << fmt("%.2f", marg * 1e3 / n) << " | "
	  << fmt("%.2f", r.mean_iterations) << " | " << fmt("%.0f", lms / n) << " / " << last.landmarks << " | " << fmt("%.0f", in_solve / n) << " | "
	  << last.prior_variables << " | " << last.prior_rank << " |\n";
	return s.str();
}

/** ms per step with the APE beside it: one row per estimator, its lagged trajectory's APE (the row
 * that follows a window's online row) in the same row; a failure as a note under its row. */
std::string timing_table(const RunReport& rep)
{
	std::ostringstream s;
	s << "| estimator | W | APE online rmse (m) | APE lagged rmse (m) | ms/step | LM solve ms/step | marginalisation ms/step "
		 "| mean LM iterations | landmarks in state (mean / end) | landmarks in the LM solve (mean) | prior variables (end) "
		 "| prior rank (end) |\n";
	s << "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
	for (std::size_t i = 0; i < rep.rows.size(); i++)
	{
		const RunRow& r = rep.rows[i];
		if (r.trajectory == "lagged") continue;
		const RunRow* lagged = (i + 1 < rep.rows.size() && rep.rows[i + 1].trajectory == "lagged") ? &rep.rows[i + 1] : nullptr;
		s << "| " << row_name(r) << " | " << window_cell(r) << " | "
		  << (r.has_ape ? fmt("%.5f", r.ape_trans.rmse) : (r.failed ? "failed" : "–")) << " | "
		  << (lagged && lagged->has_ape ? fmt("%.5f", lagged->ape_trans.rmse) : "–") << " | " << fmt("%.2f", r.ms_per_step)
		  << " | " << step_summary_cells(r);
		if (r.failed) s << "\n(" << r.label << " failed at step " << r.failed_step << ": " << r.failure << ")\n\n";
	}
	return s.str();
}

/** Mean ms/step over the tenth t (0..9) of the steps. */
double tenth_mean(const std::vector<double>& step_ms, std::size_t t)
{
	const std::size_t n = step_ms.size();
	return mean_of(step_ms, t * n / 10, (t + 1) * n / 10);
}

/** The header of a table with one column per tenth of the run and a last / first column. */
std::string tenth_header(const std::string& extra = "")
{
	std::ostringstream s;
	s << "| estimator | W |";
	for (int t = 1; t <= 10; t++) s << " " << t << "/10 |";
	s << " last / first |" << extra << "\n|---|---:|";
	for (int t = 1; t <= 10; t++) s << "---:|";
	s << "---:|" << (extra.empty() ? "" : "---|") << "\n";
	return s.str();
}

/** The per-step cost along the run: mean ms/step over each tenth of the steps, one row per estimator. */
std::string per_tenth_table(const RunReport& rep)
{
	std::ostringstream s;
	s << tenth_header();
	for (const auto& r : rep.rows)
	{
		if (r.trajectory == "lagged" || r.step_ms.empty()) continue;
		s << "| " << row_name(r) << " | " << window_cell(r) << " |";
		for (std::size_t t = 0; t < 10; t++) s << " " << fmt("%.2f", tenth_mean(r.step_ms, t)) << " |";
		s << " " << fmt("%.2f", tenth_mean(r.step_ms, 9) / tenth_mean(r.step_ms, 0)) << " |\n";
	}
	return s.str();
}

/** Per estimator: mean, p50 and p99 of ms/step, peak RSS and minor page faults per step. */
std::string cost_table(const RunReport& rep, const std::map<std::string, Resources>& resources)
{
	std::ostringstream s;
	s << "| estimator | W | ms/step mean | p50 | p99 | peak RSS (MiB) | minor page faults / step |\n";
	s << "|---|---:|---:|---:|---:|---:|---:|\n";
	for (const auto& r : rep.rows)
	{
		if (r.trajectory == "lagged" || r.step_ms.empty()) continue;
		const auto it = resources.find(r.label);
		const bool known = it != resources.end();
		s << "| " << row_name(r) << " | " << window_cell(r) << " | " << fmt("%.2f", r.ms_per_step) << " | "
		  << fmt("%.2f", quantile_of(r.step_ms, 0.5)) << " | " << fmt("%.2f", quantile_of(r.step_ms, 0.99)) << " | "
		  << (known && it->second.peak_rss_mib >= 0 ? fmt("%.0f", it->second.peak_rss_mib) : "–") << " | "
		  << (known ? fmt("%.0f", double(it->second.minor_faults) / double(r.step_ms.size())) : "–") << " |\n";
	}
	return s.str();
}

/** A row run with covariance recovery off (its label ends in kCovarianceOff). */
bool covariance_off(const RunRow& r) { return r.label.find(kCovarianceOff) != std::string::npos; }

/** Covariances on vs off, measured in the same run: per window (online row with its twin run without
 * covariances) the ms/step of each, their ratio, and the recovery's own share of the step time. */
std::string covariance_table(const RunReport& rep)
{
	std::ostringstream s;
	s << "| estimator | W | ms/step on | ms/step off | on / off | covariance ms/step | covariance share of step |\n";
	s << "|---|---:|---:|---:|---:|---:|---:|\n";
	for (const auto& on : rep.rows)
	{
		if (on.name != "window" || on.trajectory != "online" || covariance_off(on) || on.step_summaries.empty()) continue;
		for (const auto& off : rep.rows)
		{
			if (!covariance_off(off) || off.trajectory != "online" || off.window != on.window || off.policy != on.policy)
				continue;
			double cov = 0, total = 0;
			for (const auto& st : on.step_summaries)
			{
				cov += st.covariance_seconds;
				total += st.seconds;
			}
			const double n = double(on.step_summaries.size());
			s << "| " << row_name(on) << " | " << window_cell(on) << " | " << fmt("%.2f", on.ms_per_step) << " | "
			  << fmt("%.2f", off.ms_per_step) << " | " << fmt("%.3f", on.ms_per_step / off.ms_per_step) << " | "
			  << fmt("%.3f", cov * 1e3 / n) << " | " << fmt("%.1f %%", total > 0 ? 100 * cov / total : 0.0) << " |\n";
		}
	}
	return s.str();
}
}  // namespace

std::string growth_table(const GrowthRuns& runs)
{
	std::ostringstream s;
	s << tenth_header(" each run's last / first |");
	for (const auto& [row, step_ms] : runs)
	{
		double tenth[10];
		for (std::size_t t = 0; t < 10; t++)
		{
			tenth[t] = tenth_mean(step_ms.front(), t);
			for (const auto& v : step_ms) tenth[t] = std::min(tenth[t], tenth_mean(v, t));
		}
		s << "| " << row_name(*row) << " | " << window_cell(*row) << " |";
		for (double m : tenth) s << " " << fmt("%.2f", m) << " |";
		s << " " << fmt("%.2f", tenth[9] / tenth[0]) << " |";
		for (std::size_t i = 0; i < step_ms.size(); i++)
			s << (i ? ", " : " ") << fmt("%.2f", tenth_mean(step_ms[i], 9) / tenth_mean(step_ms[i], 0));
		s << " |\n";
	}
	return s.str();
}

std::string tables(const RunReport& rep, const std::string& title, const std::map<std::string, Resources>& resources)
{
	std::ostringstream s;
	s << "### " << title << "\n\n";
	s << "`" << rep.rawlog << "`: " << rep.steps << " steps, " << rep.distinct_landmarks << " landmarks observed, "
	  << rep.readings << " readings; rank-update kernel " << swba::enum_name(swba::active_simd_level())
	  << " (swba/linear/rank_update.h).\n\n";
	s << timing_table(rep);
	s << "\nCost per step (peak RSS: the process's while that estimator ran, the rawlog in memory included):\n\n";
	s << cost_table(rep, resources);
	s << "\nPer-step cost along the run (mean ms/step over each tenth of the steps):\n\n";
	s << per_tenth_table(rep);
	s << "\n";
	bool compared = false;
	for (const auto& r : rep.rows) compared = compared || covariance_off(r);
	if (compared) s << "Covariance recovery on vs off (same run):\n\n" << covariance_table(rep) << "\n";
	return s.str();
}
}  // namespace swba::bench
