/** \file sweep.h
 * `swba jobs` / `swba merge`: a sweep of `swba run` over rawlogs (or simulated rawlogs, one per seed)
 * and window sizes as independent jobs, one shell command per line of a job list, run by any
 * scheduler — GNU parallel on one or more machines, a Slurm job array — and merged afterwards into
 * the tables and plots one sequential `swba run` writes, with the same figures (doc/sweeps.md).
 *
 * Why the figures are the same: the estimators of a run are independent (each reads the rawlog and its
 * options only, and with one solver thread, the default, every solve is deterministic), so `swba run --windows 10` computes the
 * W = 10 rows exactly as `swba run --windows 5,10` does; the merge puts the jobs' rows of summary.json,
 * ape.txt and ape.csv verbatim into the order one run makes, and the table is printed from
 * summary.json, whose numbers read back exactly (nlohmann-json writes the shortest text that reads back
 * as the same double). Only the wall times (seconds, ms/step) are each job's own.
 *
 * Layout of a sweep directory DIR:
 *   sweep.json          what the merge needs: kind, groups (rawlogs), jobs with their directories
 *   config.ini          the `swba run` options of the first job of each rawlog (EKF, batch, windows)
 *   config_windows.ini  the options of the other jobs: the same with EKF, batch and causal off
 *   jobs.txt            one shell command per job; line K = job K
 *   jobs.sbatch         a Slurm array script: task K runs line K of jobs.txt
 *   jobs/<rawlog>/w<W>/ each job's `swba run` output ("all" instead of w<W> for a NEES job)
 */
#pragma once

#include <swba/apps/run.h>
#include <swba/apps/run_options.h>
#include <swba/core/names.h>

#include <array>
#include <cstddef>
#include <iosfwd>
#include <string>
#include <vector>

namespace swba::apps
{
/** What the jobs of a sweep compute, and so what `swba merge` makes of them. */
enum class SweepKind
{
	Run,  ///< "run": one job per rawlog × W; merged into swba run's tables (APE across W)
	Nees  ///< "nees": one job per seed (every W); merged into the average NEES (swba/apps/nees.h)
};
constexpr std::array<EnumName<SweepKind>, 2> enum_names(SweepKind)
{
	return {{{SweepKind::Run, "run"}, {SweepKind::Nees, "nees"}}};
}

struct SweepOptions
{
	SweepKind kind = SweepKind::Run;
	/** Rawlogs to run on (ground truth: <name>_ground_truth_robot_path.txt next to each, if present; for an
	 * inertial rawlog <name>_ground_truth.tum). */
	std::vector<std::string> rawlogs;
	/** simul-landmarks INI: one simulated rawlog per seed, made by the job itself (swba simulate). */
	std::string simulate_ini;
	/** Seeds of the simulated rawlogs (each ≥ 1, distinct). */
	std::vector<long> seeds;
	/** The `swba run` options of every job; run.windows are the windows swept. rawlog, ground_truth
	 * and out_dir are set per job. */
	RunOptions run;
	/** The sweep directory, created. (Default = "swba_sweep") */
	std::string dir = "swba_sweep";
	/** The swba executable the job lines call (an absolute path, or a name on every machine's PATH). */
	std::string swba = "swba";

	/** Throws std::invalid_argument naming the option. */
	void validate() const;
};

/** A rawlog of the sweep and the jobs that run on it. */
struct SweepGroup
{
	std::string name;			 ///< file-safe, unique: the rawlog's stem, or <INI stem>_seed<S>
	std::string rawlog;			 ///< absolute path ("" for a simulated one: each job makes its own)
	std::string ground_truth;	 ///< absolute path, "" = none
	long seed = 0;				 ///< simulated rawlogs: the seed
	/** An inertial (observation-format) rawlog: one job runs every window and the merge takes its report
	 * as it is (the inertial rows are not split by W). */
	bool inertial = false;
	std::vector<std::size_t> jobs;	///< ids of its jobs, in window order
};

struct SweepJob
{
	std::size_t id = 0;	 ///< 1-based: line of jobs.txt, Slurm's SLURM_ARRAY_TASK_ID
	std::size_t group = 0;	///< index into SweepPlan::groups
	int window = 0;		 ///< W of the job; 0 = every window of the configuration
	std::string dir;	 ///< the job's output directory, relative to the sweep directory
	std::string command; ///< one shell command line
};

struct SweepPlan
{
	SweepKind kind = SweepKind::Run;
	std::string dir;		   ///< absolute
	std::string simulate_ini;  ///< absolute, "" = real rawlogs
	std::vector<int> windows;
	int threads = 1;		   ///< solver threads of each job (Slurm's --cpus-per-task)
	std::vector<SweepGroup> groups;
	std::vector<SweepJob> jobs;
};

/** The jobs: for a run sweep one per rawlog × W (the first W of each rawlog also runs the EKF, the batch
 * and the causal optimum) and one per inertial rawlog (every W), for a NEES sweep one per seed. Paths in the commands are absolute. */
SweepPlan plan_sweep(const SweepOptions& options);

/** "1-5,9" → {1, 2, 3, 4, 5, 9}. Throws std::invalid_argument naming `what` on an empty item, a
 * non-integer, a seed < 1, a reversed range or a seed given twice. */
std::vector<long> parse_seed_list(const std::string& text, const std::string& what = "--seeds");

/** A word for the shell: unchanged when it has only safe characters, else in single quotes. */
std::string shell_quote(const std::string& word);

/** jobs.txt: the command lines. */
std::string format_job_list(const SweepPlan& plan);
/** jobs.sbatch: `#SBATCH --array=1-N`, runs line $SLURM_ARRAY_TASK_ID of jobs.txt. */
std::string format_sbatch_script(const SweepPlan& plan);
/** sweep.json. */
std::string format_sweep_manifest(const SweepPlan& plan);

/** Writes the sweep directory (config.ini, config_windows.ini, jobs.txt, jobs.sbatch, sweep.json) and,
 * with `say_how_to_run`, says on `log` how to run the jobs (GNU parallel, Slurm) and merge them; a
 * caller that runs them itself says so instead; `program` names the command in that line. Throws
 * std::runtime_error naming a path that cannot be written. */
void write_sweep(const SweepOptions& options, const SweepPlan& plan, std::ostream& log, bool say_how_to_run = true,
				 const std::string& program = "swba jobs");

/** Reads DIR/sweep.json. Throws std::runtime_error naming the file and what is wrong. */
SweepPlan read_sweep_manifest(const std::string& dir);

/** The directory of a job (absolute). */
std::string job_directory(const SweepPlan& plan, const SweepJob& job);

/** Checks each job's summary.json: every job that has none (or an interrupted one) gets a line on
 * `log`, then std::runtime_error says how many and how to re-run them. */
void check_jobs_complete(const SweepPlan& plan, std::ostream& log);

struct MergeOptions
{
	/** The sweep directory (written by swba jobs or swba nees --jobs-only). */
	std::string dir;
	/** Where the merged files go; "" = <dir>/merged. */
	std::string out_dir;
	/** Write gnuplot plots when gnuplot is found. (Default = true) */
	bool plots = true;
	/** The command its messages on the log name. (Default = "swba merge") */
	std::string program = "swba merge";
};

/** One merged report per rawlog. */
struct RunMerge
{
	std::vector<RunReport> reports;
	std::vector<std::string> files;
};

/** Merges the jobs of a run sweep: per rawlog, <out>/<rawlog name>/ gets what `swba run` writes (TUM
 * and *.cov files copied from the jobs, ape.txt, ape.csv, summary.json, config.ini, plots) and the
 * comparison table goes to `out`; with several rawlogs also ape_across_rawlogs.txt/.csv (APE rmse per
 * estimator over the rawlogs). Throws std::runtime_error on a missing or inconsistent job. */
RunMerge merge_run_sweep(const SweepPlan& plan, const MergeOptions& options, std::ostream& out, std::ostream& log);

/** `swba merge`: reads DIR/sweep.json and merges a run sweep (merge_run_sweep) or a NEES sweep
 * (merge_nees_sweep, swba/apps/nees.h). Returns the exit code (0). Throws std::runtime_error on a
 * missing or inconsistent job. */
int merge_sweep(const MergeOptions& options, std::ostream& out, std::ostream& log);
}  // namespace swba::apps
