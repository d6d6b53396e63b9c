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
#include "bench_tables.h"

#include <swba/apps/run.h>
#include <swba/apps/simulate.h>
#include <swba/eval/ground_truth.h>

#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <mrpt/system/filesystem.h>

#include <sys/resource.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace
{
using swba::apps::RunOptions;
using swba::apps::RunReport;
using swba::apps::RunRow;
using swba::bench::kCovarianceOff;
using swba::bench::Resources;

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
	swba::bench::GrowthRuns rows;
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
	  << swba::bench::growth_table(rows) << "\n";
	return s.str();
}

/** Runs one rawlog, prints its tables to stdout and returns them (for --markdown); with `growth` > 1 the
 * growth table of the SLAM window over that many runs. */
std::string bench_rawlog(const RunOptions& base, const std::string& rawlog, const StepLimits& limits,
						 const std::string& title, bool compare_covariance, int growth = 1)
{
	const BenchInput in = read_input(rawlog, limits.read);
	const RunReport rep = run_rawlog(base, in, limits, compare_covariance);
	const std::string t = swba::bench::tables(rep, title, row_resources()) + growth_section(base, in, limits, growth, rep);
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
