/** \file nees.h
 * `swba nees`: filter consistency by Monte Carlo. N simulated rawlogs (simul-landmarks, seeds
 * first_seed … first_seed + N − 1), the chosen estimators on each (one `swba run` per seed: the window
 * online and lagged at each W, FEJ on and off, MRPT's EKF), then per estimator and step the average
 * over the N runs of the position NEES (3 dof) and the pose NEES (6 dof) against the 95 % χ² band of
 * such an average (swba/eval/nees.h for the definitions; doc/sweeps.md).
 *
 * The runs are the jobs of a NEES sweep (swba/apps/sweep.h): `swba nees` writes the job list, runs
 * it here one job after the other and merges; `swba nees --jobs-only` stops after writing it, the
 * jobs run on GNU parallel or Slurm, and `swba merge DIR` computes the same table — the same code
 * on the same files, so the same numbers. */
#pragma once

#include <swba/apps/run_options.h>
#include <swba/apps/sweep.h>
#include <swba/eval/nees.h>

#include <cstddef>
#include <iosfwd>
#include <string>
#include <vector>

namespace swba::apps
{
struct NeesOptions
{
	/** Number of simulated runs N (≥ 1). (Default = 50) */
	int runs = 50;
	/** Seed of the first run; run i has seed first_seed + i. (Default = 1) */
	long first_seed = 1;
	/** simul-landmarks INI (required; the CLI defaults to share/rawlogs/kf-slam_6D_noisy.ini: 600
	 * steps, 6D). */
	std::string ini;
	/** The `swba run` options of every run. Defaults here: W = 10, FEJ on and off, EKF kfEKFAlaDavison,
	 * no batch, no plots. */
	RunOptions run = default_run_options();
	/** Sweep directory, created. (Default = "swba_nees") */
	std::string dir = "swba_nees";
	/** The swba executable of the job lines. */
	std::string swba = "swba";
	/** Write the job list and stop (run it with GNU parallel or Slurm, then swba merge DIR). (Default = false) */
	bool jobs_only = false;
	/** Write gnuplot plots of the average NEES. (Default = true) */
	bool plots = true;

	static RunOptions default_run_options();
	/** Throws std::invalid_argument naming the option. */
	void validate() const;
	/** The sweep: kind Nees, --simulate ini, the seeds. */
	SweepOptions sweep_options() const;
};

/** One estimator's NEES over the runs. */
struct NeesEstimator
{
	std::string label;				   ///< the swba run row label, e.g. "window W=10 slam fej lagged"
	std::size_t runs = 0;			   ///< runs that entered the average (the estimator did not fail)
	std::vector<std::string> failures; ///< "seed S: failed at step k: …" for each run left out
	/** Poses with every dof fixed (zero covariance), left out, over all runs (eval::RunNees::fixed_poses). */
	std::size_t fixed_poses = 0;
	eval::AverageNees average;
};

struct NeesReport
{
	std::string simulate_ini;
	std::vector<long> seeds;
	std::size_t steps = 0;	///< steps of the first run
	std::vector<NeesEstimator> estimators;
	std::vector<std::string> files;
};

/** Reads the jobs' TUM and covariance files and the ground truth and averages the NEES per estimator;
 * writes nees.txt, nees.csv and the plots nees_position, nees_pose into options.out_dir (default
 * DIR/nees) and prints the table on `out`. Throws std::runtime_error naming the first covariance file
 * that is missing (swba run writes <stem>.cov next to each TUM file) or malformed. */
NeesReport merge_nees_sweep(const SweepPlan& plan, const MergeOptions& options, std::ostream& out, std::ostream& log);

/** The table: per estimator the runs, and for position and pose NEES the dof, the band, the share of
 * steps whose average is in it and the mean of the average over the steps. */
std::string format_nees_table(const NeesReport& report);
/** nees.csv: one row per estimator and step; numbers with 17 significant digits (exact). */
std::string format_nees_csv(const NeesReport& report);

/** The whole `swba nees`: writes the sweep, runs its jobs one after the other (each job's output in
 * <job dir>/job.log; progress on `log`), then merge_nees_sweep. With jobs_only, stops after writing
 * the sweep. Returns the exit code. Throws std::runtime_error when a job fails (naming it, its log and
 * how to re-run it). */
int run_nees_app(const NeesOptions& options, std::ostream& out, std::ostream& log);
}  // namespace swba::apps
