// swba_bench_window: in one run, ms per step of the sliding window (each W, both landmark policies)
// and of MRPT's EKF on kf-slam_6D_demo and on the 5000-step / 400-landmark simulated rawlog
// (share/rawlogs/large_6D_5000.ini, made with `swba simulate` when missing), with the
// APE (translation rmse, not aligned) beside each time, where the window's time goes (LM solve vs
// marginalisation, state size), and the per-step cost along the run (mean ms/step over each tenth).
// With --covariance-off the window also runs with covariance recovery off, and a table compares the two
// in the same run (the ratio of ms/step, fastest of three alternating runs each, and the recovery's own
// share of the step time).
// A cost table gives, per estimator, the mean, median and 99th percentile of ms/step, its peak resident
// set size and its minor page faults per step (heap churn): the peak is reset before each estimator
// (Linux: /proc/self/clear_refs) and read after it (VmHWM), so each row's figure is its own.
// A growth table runs the SLAM window on the large rawlog --growth-runs times in all and gives per tenth of
// the run the fastest run's mean ms/step and its last / first tenth (one run's tenths moved by up to ±30 %
// on a shared machine), beside every run's own last / first.
// A benchmark, not a test: timings vary ±25 % between runs on shared machines; compare within a run.
#include <swba/apps/run.h>
#include <swba/apps/simulate.h>
#include <swba/eval/ground_truth.h>
#include <swba/linear/rank_update.h>

#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <mrpt/system/filesystem.h>

#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace
{
using swba::apps::RunOptions;
using swba::apps::RunReport;
using swba::apps::RunRow;

std::string fmt(const char* f, double v)
{
	char buf[64];
	std::snprintf(buf, sizeof(buf), f, v);
	return buf;
}

/** What one estimator used besides time: its peak resident set and the minor page faults it caused. */
struct Resources
{
	double peak_rss_mib = -1;  ///< −1: unknown (no /proc)
	long minor_faults = 0;
};

/** Resources per row label, filled by ResourceMeter as rows finish. */
std::map<std::string, Resources>& row_resources()
{
	static std::map<std::string, Resources> r;
	return r;
}

/** Measures each estimator of a run_estimators call from its row_done callbacks: between two callbacks
 * only the rows added in between ran (rows run one after another). */
class ResourceMeter
{
   public:
	ResourceMeter() { reset(); }
	/** Attributes what was used since the last call to rows [first, report.rows.size()) and restarts. */
	void rows_done(const RunReport& report, const std::string& suffix)
	{
		Resources r;
		r.peak_rss_mib = peak_rss_mib();
		r.minor_faults = minor_faults() - faults_at_start_;
		for (std::size_t i = first_; i < report.rows.size(); i++) row_resources()[report.rows[i].label + suffix] = r;
		first_ = report.rows.size();
		reset();
	}

   private:
	static long minor_faults()
	{
		rusage u{};
		getrusage(RUSAGE_SELF, &u);
		return u.ru_minflt;
	}
	/** VmHWM of /proc/self/status in MiB, −1 when it cannot be read. */
	static double peak_rss_mib()
	{
		std::ifstream f("/proc/self/status");
		std::string line;
		while (std::getline(f, line))
			if (line.rfind("VmHWM:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
		return -1;
	}
	void reset()
	{
		std::ofstream("/proc/self/clear_refs") << "5";  // resets VmHWM to the current RSS
		faults_at_start_ = minor_faults();
	}
	std::size_t first_ = 0;
	long faults_at_start_ = 0;
};

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

/** The SLAM-policy window's growth along the run over several runs: `runs` holds each run's step times by
 * row label (the main tables' run first). Per tenth the fastest run's mean (the least disturbed by other
 * load on a shared machine), its last / first, and every run's own last / first. */
std::string growth_table(const std::vector<std::pair<const RunRow*, std::vector<std::vector<double>>>>& runs)
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

/** Per estimator: mean, p50 and p99 of ms/step, peak RSS and minor page faults per step. */
std::string cost_table(const RunReport& rep)
{
	std::ostringstream s;
	s << "| estimator | W | ms/step mean | p50 | p99 | peak RSS (MiB) | minor page faults / step |\n";
	s << "|---|---:|---:|---:|---:|---:|---:|\n";
	for (const auto& r : rep.rows)
	{
		if (r.trajectory == "lagged" || r.step_ms.empty()) continue;
		const auto it = row_resources().find(r.label);
		const bool known = it != row_resources().end();
		s << "| " << row_name(r) << " | " << window_cell(r) << " | " << fmt("%.2f", r.ms_per_step) << " | "
		  << fmt("%.2f", quantile_of(r.step_ms, 0.5)) << " | " << fmt("%.2f", quantile_of(r.step_ms, 0.99)) << " | "
		  << (known && it->second.peak_rss_mib >= 0 ? fmt("%.0f", it->second.peak_rss_mib) : "–") << " | "
		  << (known ? fmt("%.0f", double(it->second.minor_faults) / double(r.step_ms.size())) : "–") << " |\n";
	}
	return s.str();
}

/** Label suffix of the rows run with covariance recovery off (--covariance-off). */
constexpr const char* kCovarianceOff = " (covariances off)";

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

/** The markdown tables of one rawlog. */
std::string tables(const RunReport& rep, const std::string& title)
{
	std::ostringstream s;
	s << "### " << title << "\n\n";
	s << "`" << rep.rawlog << "`: " << rep.steps << " steps, " << rep.distinct_landmarks << " landmarks observed, "
	  << rep.readings << " readings; rank-update kernel " << swba::enum_name(swba::active_simd_level())
	  << " (swba/linear/rank_update.h).\n\n";
	s << timing_table(rep);
	s << "\nCost per step (peak RSS: the process's while that estimator ran, the rawlog in memory included):\n\n";
	s << cost_table(rep);
	s << "\nPer-step cost along the run (mean ms/step over each tenth of the steps):\n\n";
	s << per_tenth_table(rep);
	s << "\n";
	bool compared = false;
	for (const auto& r : rep.rows) compared = compared || covariance_off(r);
	if (compared) s << "Covariance recovery on vs off (same run):\n\n" << covariance_table(rep) << "\n";
	return s.str();
}

/** How many steps of a rawlog to read, and how many of those the EKF and the SLAM-policy window get
 * (0 = all; the constant-time and map windows always get every step read). */
struct StepLimits
{
	std::size_t read = 0, ekf = 0, slam_window = 0;
};

/** The command line: every option, and the run options and large rawlog it names. */
struct BenchCommandLine
{
	TCLAP::CmdLine cmd{"Sliding window (every landmark policy) vs MRPT's EKF: ms per step with APE, on "
					   "kf-slam_6D_demo and a 5000-step / 400-landmark simulated rawlog.",
					   ' ', "0.1.0"};
	TCLAP::ValueArg<std::string> small{"", "small", "the small rawlog. (Default: kf-slam_6D_demo.rawlog)", false,
									   std::string(SWBA_MRPT_DATASETS) + "/kf-slam_6D_demo.rawlog", "RAWLOG"};
	TCLAP::ValueArg<std::string> large{
		"", "large",
		"the large rawlog. (Default: <rawlog-dir>/large_6D_5000_seed123.rawlog, made by swba simulate from "
		"share/rawlogs/large_6D_5000.ini with its own seed if missing)",
		false, "", "RAWLOG"};
	TCLAP::ValueArg<std::string> rawlog_dir{"", "rawlog-dir", "where generated rawlogs go. (Default: <build>/rawlogs)",
											false, SWBA_BENCH_RAWLOG_DIR, "DIR"};
	TCLAP::ValueArg<std::string> windows{"", "windows", "window sizes. (Default: 10,30)", false, "10,30", "LIST"};
	TCLAP::ValueArg<std::string> policy{"", "policy", "slam, constant-time, map, a comma-separated list, both or all. (Default: all)",
										false, "all", "P"};
	TCLAP::ValueArg<std::string> ekf_method{"", "ekf-method", "EKF methods. (Default: kfEKFAlaDavison)", false,
											"kfEKFAlaDavison", "NAMES"};
	TCLAP::ValueArg<int> large_steps{"", "large-steps", "steps of the large rawlog to run (0 = all). (Default: 0)",
									 false, 0, "N"};
	TCLAP::ValueArg<int> ekf_large_steps{
		"", "ekf-large-steps",
		"steps of the large rawlog given to the EKF (0 = all; its cost grows with the map, so a prefix "
		"under-states it). (Default: 0)",
		false, 0, "N"};
	TCLAP::ValueArg<int> slam_large_steps{
		"", "slam-large-steps",
		"steps of the large rawlog given to the SLAM-policy window (0 = all; its prior holds every landmark seen, "
		"so its cost grows with the map: quadratically with landmark IDs, cubically with data association). "
		"(Default: 0)",
		false, 0, "N"};
	TCLAP::SwitchArg no_small{"", "no-small", "skip the small rawlog"};
	TCLAP::SwitchArg no_large{"", "no-large", "skip the large rawlog"};
	TCLAP::MultiArg<std::string> real{
		"", "real",
		"a real robot's rawlog, benchmarked like the small one (repeatable). (Default: the five MRCLAM logs of "
		"share/data/mrclam)",
		false, "RAWLOG"};
	TCLAP::SwitchArg no_real{"", "no-real", "skip the real rawlogs"};
	TCLAP::SwitchArg no_ekf{"", "no-ekf", "skip the EKF"};
	TCLAP::ValueArg<std::string> markdown{"", "markdown", "also write the tables to FILE", false, "", "FILE"};
	TCLAP::ValueArg<std::string> config{
		"", "config",
		"swba run's INI (doc/run.md) for the window's and solver's options, e.g. [solver] max_iterations; the "
		"rawlog, windows, policies and EKF methods still come from this command line. (Default: built-in)",
		false, "", "INI"};
	TCLAP::SwitchArg covariance_off{"", "covariance-off",
									"also run each window with covariance recovery off, and compare (same run)"};
	TCLAP::ValueArg<int> growth_runs{
		"", "growth-runs",
		"runs of the SLAM-policy window on the large rawlog for the growth table (per tenth of the run the "
		"fastest run's mean ms/step; the first run is the main tables'; 1 = no table). (Default: 3)",
		false, 3, "N"};
	TCLAP::SwitchArg keep_prior_only{
		"", "keep-prior-only-landmarks",
		"solve with every landmark of the prior in the LM problem (SlidingWindowOptions::eliminate_prior_only_landmarks "
		"= false), for comparison"};

	BenchCommandLine()
	{
		// TCLAP lists options in reverse order of addition.
		for (TCLAP::Arg* a : std::initializer_list<TCLAP::Arg*>{
				 &no_real, &real, &growth_runs, &covariance_off, &keep_prior_only, &config, &markdown, &no_ekf, &no_large, &no_small, &slam_large_steps,
				 &ekf_large_steps, &large_steps, &ekf_method, &policy, &windows, &rawlog_dir, &large, &small})
			cmd.add(*a);
	}

	/** The options of every run: the INI of --config (or the built-in defaults), then the windows,
	 * policies and EKF methods of this command line; never the batch, never plots. TCLAP reads are not const. */
	RunOptions run_options()
	{
		RunOptions o;
		if (!config.getValue().empty()) swba::apps::load_run_config(config.getValue(), o);
		if (keep_prior_only.getValue()) o.window.eliminate_prior_only_landmarks = false;
		o.windows = swba::apps::parse_window_list(windows.getValue(), "--windows");
		o.policies = swba::apps::parse_policy_list(policy.getValue());
		o.ekf_methods = swba::apps::parse_ekf_method_list(ekf_method.getValue());
		o.run_ekf = !no_ekf.getValue();
		o.run_batch = false;
		o.plots = false;
		return o;
	}

	/** The step limits of the large rawlog (a negative count means all). */
	StepLimits large_step_limits()
	{
		const auto at_least_0 = [](int n) { return std::size_t(std::max(0, n)); };
		return {at_least_0(large_steps.getValue()), at_least_0(ekf_large_steps.getValue()),
				at_least_0(slam_large_steps.getValue())};
	}

	/** --large, else <rawlog-dir>/large_6D_5000_seed123.rawlog, made when missing as `swba simulate` makes
	 * a run (doc/sweeps.md): simul-landmarks with the INI's own seed, its motionless start declared exact
	 * (written without noise, it would otherwise let every estimator's map anchor wander by the declared
	 * σ, which decides the unaligned APE of the whole run). */
	std::string large_rawlog()
	{
		if (!large.getValue().empty()) return large.getValue();
		swba::apps::SimulateOptions so;
		so.ini = std::string(SWBA_SOURCE_DIR) + "/share/rawlogs/large_6D_5000.ini";
		so.seed = 123;  // [Params] random_seed of that INI
		so.out_dir = rawlog_dir.getValue();
		const std::string path = so.out_dir + "/" + so.output_name() + ".rawlog";
		if (mrpt::system::fileExists(path)) return path;
		std::cerr << "bench: generating " << path << " (swba simulate " << so.ini << " --seed " << so.seed << ")\n";
		return swba::apps::simulate_rawlog(so, std::cerr).rawlog;
	}
};

/** A rawlog's steps and its ground truth (empty when eval::default_ground_truth_path names no file). */
struct BenchInput
{
	swba::io::Rawlog log;
	std::vector<mrpt::poses::CPose3D> gt;
};

/** Reads the first `steps` steps of `rawlog` (0 = all) and its ground truth if present. */
BenchInput read_input(const std::string& rawlog, std::size_t steps)
{
	swba::io::RawlogReaderOptions ro;
	ro.max_steps = steps;
	BenchInput in;
	in.log = swba::io::read_rawlog(rawlog, ro);
	const std::string gt_path = swba::eval::default_ground_truth_path(rawlog);
	if (mrpt::system::fileExists(gt_path)) in.gt = swba::eval::read_ground_truth_for(gt_path, in.log.steps.size());
	std::cerr << "bench: " << rawlog << ": " << in.log.steps.size() << " steps\n";
	return in;
}

/** Runs `o` on the first `n` steps of the input (0 = all) and appends its rows to `rep`, labelled
 * "(first n steps)" when that is fewer than were read. Nothing when `o` runs no estimator. */
void run_part(const RunOptions& o, const BenchInput& in, std::size_t n, RunReport& rep)
{
	const std::string suffix = o.window.covariances ? "" : kCovarianceOff;
	if (o.windows.empty() && !o.run_ekf) return;
	auto part = in.log;
	if (n && n < part.steps.size()) part.steps.resize(n);
	std::string label_suffix = part.steps.size() < in.log.steps.size() ? " (first " + std::to_string(part.steps.size()) + " steps)" : "";
	label_suffix += suffix;
	ResourceMeter meter;
	swba::apps::RunControl control;
	control.row_done = [&](const RunReport& partial) { meter.rows_done(partial, label_suffix); };
	auto r = swba::apps::run_estimators(o, part, in.gt, std::cerr, control);
	for (auto& row : r.rows)
	{
		row.label += label_suffix;
		rep.rows.push_back(std::move(row));
	}
}

/** The window of `w` with covariances on and off, alternately kCovarianceRepeats times each, keeping the
 * fastest run of each (the minimum is what other load on a shared machine disturbs least; single runs
 * of the two differed by up to ±25 % either way, and the first run of a process is slower). */
void run_covariance_pair(const RunOptions& w, const BenchInput& in, std::size_t n, RunReport& rep)
{
	constexpr int kCovarianceRepeats = 5;
	RunOptions off = w;
	off.window.covariances = false;
	RunReport best_on, best_off;
	const auto keep_faster = [](RunReport& best, RunReport&& r) {
		if (best.rows.empty() || (!r.rows.empty() && r.rows[0].ms_per_step < best.rows[0].ms_per_step)) best = std::move(r);
	};
	for (int i = 0; i < kCovarianceRepeats; i++)
	{
		RunReport a, b;
		run_part(w, in, n, a);
		run_part(off, in, n, b);
		keep_faster(best_on, std::move(a));
		keep_faster(best_off, std::move(b));
	}
	for (auto* r : {&best_on, &best_off})
		for (auto& row : r->rows) rep.rows.push_back(std::move(row));
}

/** One rawlog: the EKF and the window of each policy, each on its own number of steps, rows merged
 * into one report. */
RunReport run_rawlog(const RunOptions& base, const BenchInput& in, const StepLimits& limits, bool compare_covariance)
{
	RunReport rep;
	rep.rawlog = in.log.path;
	rep.steps = in.log.steps.size();
	rep.distinct_landmarks = in.log.distinct_landmarks;
	rep.readings = in.log.readings;
	RunOptions ekf = base;
	ekf.windows.clear();
	if (base.run_ekf) run_part(ekf, in, limits.ekf, rep);
	for (const auto policy : base.policies)
	{
		RunOptions w = base;
		w.run_ekf = false;
		w.policies = {policy};
		const std::size_t n = policy == swba::estimators::LandmarkPolicy::Slam ? limits.slam_window : 0;
		if (compare_covariance)
			run_covariance_pair(w, in, n, rep);
		else
			run_part(w, in, n, rep);
	}
	return rep;
}

/** The SLAM-policy window of `base` on the input `in` run `runs` − 1 more times, its online rows' step times
 * beside those of `rep` (the first run), as a growth table. Empty when there is no such row or runs < 2. */
std::string growth_section(const RunOptions& base, const BenchInput& in, const StepLimits& limits, int runs,
						   const RunReport& rep)
{
	std::vector<std::pair<const RunRow*, std::vector<std::vector<double>>>> rows;
	for (const auto& r : rep.rows)
		if (r.name == "window" && r.policy == "slam" && r.trajectory == "online" && !r.step_ms.empty() && !r.failed)
			rows.push_back({&r, {r.step_ms}});
	if (rows.empty() || runs < 2) return "";
	RunOptions w = base;
	w.run_ekf = false;
	w.policies = {swba::estimators::LandmarkPolicy::Slam};
	for (int i = 1; i < runs; i++)
	{
		RunReport again;
		run_part(w, in, limits.slam_window, again);
		for (auto& [row, step_ms] : rows)
			for (const auto& r : again.rows)
				if (r.label == row->label && r.trajectory == "online") step_ms.push_back(r.step_ms);
	}
	std::ostringstream s;
	s << "Growth of the SLAM window's cost along the run over " << runs
	  << " runs (mean ms/step per tenth of the steps, the fastest run's):\n\n"
	  << growth_table(rows) << "\n";
	return s.str();
}

/** Runs one rawlog, prints its tables to stdout and returns them (for --markdown); with `growth` > 1 the
 * growth table of the SLAM window over that many runs. */
std::string bench_rawlog(const RunOptions& base, const std::string& rawlog, const StepLimits& limits,
						 const std::string& title, bool compare_covariance, int growth = 1)
{
	const BenchInput in = read_input(rawlog, limits.read);
	const RunReport rep = run_rawlog(base, in, limits, compare_covariance);
	const std::string t = tables(rep, title) + growth_section(base, in, limits, growth, rep);
	std::cout << t << std::flush;
	return t;
}

/** Writes the tables of every rawlog to FILE of --markdown. Throws naming the file it cannot write. */
void write_markdown(const std::string& path, const std::string& text)
{
	std::ofstream f(path);
	f << text;
	if (!f) throw std::runtime_error("cannot write " + path);
}
}  // namespace

int main(int argc, char** argv)
{
	try
	{
		BenchCommandLine cl;
		if (!cl.cmd.parse(argc, argv)) return 0;
		if (cl.growth_runs.getValue() < 1) throw std::invalid_argument("--growth-runs must be at least 1");
		const RunOptions base = cl.run_options();
		std::string all;
		const bool cov = cl.covariance_off.getValue();
		if (!cl.no_small.getValue())
			all += bench_rawlog(base, cl.small.getValue(), {}, mrpt::system::extractFileName(cl.small.getValue()), cov);
		if (!cl.no_large.getValue())
		{
			const std::string large = cl.large_rawlog();
			all += bench_rawlog(base, large, cl.large_step_limits(), mrpt::system::extractFileName(large), cov,
								cl.growth_runs.getValue());
		}
		std::vector<std::string> real = cl.real.getValue();
		if (real.empty())
			for (int r = 1; r <= 5; r++)
				real.push_back(std::string(SWBA_SOURCE_DIR) + "/share/data/mrclam/mrclam6_r" + std::to_string(r) + ".rawlog");
		if (!cl.no_real.getValue())
			for (const auto& f : real) all += bench_rawlog(base, f, {}, mrpt::system::extractFileName(f), cov);
		if (!cl.markdown.getValue().empty()) write_markdown(cl.markdown.getValue(), all);
		return 0;
	}
	catch (const std::exception& e)
	{
		std::cerr << "swba_bench_window: error: " << e.what() << "\n";
		return 1;
	}
}
