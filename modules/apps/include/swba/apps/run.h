/** \file run.h
 * `swba run`: every estimator on the same rawlog — MRPT's EKF (each method), the sliding window for
 * each W (online and lagged trajectories, each landmark policy and FEJ setting asked for), the batch
 * solution and optionally the full-history causal optimum — then APE against the ground truth, a
 * comparison table and the files of doc/run.md (TUM trajectories, ape.txt, ape.csv, summary.json,
 * plots). An estimator that fails (MRPT's EKF throws on kf-slam_6D_demo_noncentered) becomes a row
 * with the step and the message; it never aborts the run.
 *
 * Pairing with the ground truth (swba/eval/ground_truth.h): the estimate after step k has time
 * t = k + 1 and is compared with GT row k + 1 (row i = the true pose when SF_i was taken); APE is
 * not aligned. */
#pragma once

#include <swba/apps/run_options.h>
#include <swba/estimators/association_quality.h>
#include <swba/estimators/sliding_window.h>
#include <swba/eval/metrics.h>
#include <swba/eval/trajectory.h>
#include <swba/io/rawlog.h>

#include <mrpt/poses/CPose3D.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

namespace swba::apps
{
/** A row's consistency against the ground truth: the NEES of its estimate with its own covariance, one
 * run's (swba/eval/nees.h), averaged over the poses that have a covariance. */
struct RowNees
{
	std::size_t poses = 0;  ///< poses with a covariance (a pose whose every dof is fixed is left out)
	double position_mean = 0, pose_mean = 0;
	int position_dof = 0, pose_dof = 0;  ///< of one pose (planar: 2 and 3)
	/** Share of those poses whose NEES lies in the two-sided 95 % χ² band of one run (a consistent
	 * estimate: about 0.95). */
	double position_in_band = 0, pose_in_band = 0;
};

/** One estimator's result: one row of the comparison table, one entry of summary.json. */
struct RunRow
{
	RunRow() = default;
	/** A row with only its identity set; the estimator fills in the rest (and names the file, if any). */
	RunRow(std::string name, std::string label, std::string trajectory, int window = 0);

	std::string name;        ///< "ekf", "window", "batch" or "causal"
	std::string label;       ///< unique display name, e.g. "window W=10", "window W=10 slam nofej", "ekf kfEKFNaive"
	int window = 0;          ///< W for window rows; 0 = none (null in JSON)
	std::string trajectory;  ///< "online" (EKF, window online, causal), "lagged" (window), "smoothed" (batch)
	std::string policy;      ///< window rows: "slam" / "constant-time"; else ""
	std::optional<bool> fej; ///< window rows: first-estimate Jacobians on/off
	std::string method;      ///< EKF rows: MRPT's method name
	std::string file;        ///< TUM file name inside the output directory ("" = not written)
	eval::Trajectory estimate;  ///< t = k + 1 for the pose after step k
	/** The marginal covariance of each pose of `estimate` (same order; doc/formats.md, "Covariance
	 * files"), as the estimator had it for that pose: EKF and window online after its step, lagged when
	 * it left the window, batch at the solution. Empty: none (causal rows, covariances off). */
	std::vector<estimators::PoseCovariance> covariance;
	/** The final landmark estimates with their covariance (in the frame of `estimate`); with `covariance`. */
	std::map<std::int32_t, estimators::LandmarkEstimate> landmarks;
	/** Seconds spent recovering the covariances (window: all steps and the final landmarks; batch: at
	 * the solution; null for the EKF, whose covariance is its state, and rows without). */
	std::optional<double> covariance_seconds;

	bool has_ape = false;    ///< false without ground truth or when the estimator failed
	eval::Statistics ape_trans, ape_full;  ///< APE translation part (m), full transformation (unit-less)
	eval::Statistics ape_rot;  ///< APE rotation angle (deg), with has_ape
	/** RPE translation part (m) between consecutive estimates (δ = 1 step, evo_rpe's default): the
	 * drift per step; with has_rpe (has_ape and at least two poses). */
	eval::Statistics rpe_trans;
	bool has_rpe = false;
	std::vector<double> ape_trans_errors;  ///< per pose of `estimate`: APE translation part (m), for the plots
	/** Rows with ground truth and `covariance`: how consistent the covariance is with the error. */
	std::optional<RowNees> nees;
	std::string nees_error;  ///< why `nees` could not be computed (a covariance not positive definite), one line

	double seconds = 0;      ///< wall time of the estimator (all its steps, or the batch solve)
	double ms_per_step = 0;  ///< seconds·1000 / steps processed
	std::size_t steps = 0;   ///< steps processed
	/** Wall time of each step in milliseconds (window and EKF rows; empty for batch). The lagged row
	 * shares the run of its online row and has the same numbers. */
	std::vector<double> step_ms;
	double mean_iterations = 0;  ///< window rows: mean LM iterations per step; batch: iterations
	/** Batch rows: the start of the solve ("dead reckoning" or "lagged W=<n>") and its final cost (the
	 * run keeps the start with the lower cost as the batch row and reports the other as batch_alt). */
	std::string start;
	std::optional<double> final_cost;
	/** Window, batch and causal rows: what the χ² gate and the robust loss did with the readings (the
	 * lagged row shares its online row's). Null for the EKF. */
	std::optional<estimators::ReadingCounts> reading_counts;
	/** Window rows: what each process() call did (solve/marginalisation time, state size), for
	 * benchmarks. Empty for other rows. */
	std::vector<estimators::StepSummary> step_summaries;
	/** Window rows (and the batch, which takes them from the last window run): the landmark ID each
	 * reading of each step was given (estimators::SlidingWindowEstimator::assigned_ids). */
	estimators::ReadingIds assigned_ids;
	/** Rows with assigned_ids, when the run uses data association and the truth is known (the
	 * readings' own IDs, or the simulator's landmark ground truth): how right it was. */
	std::optional<estimators::AssociationQuality> association;

	/** The row's estimate left its readings (not finite, or a median reading misfit above the limit;
	 * doc/realdata.md): its figures are not a result. The table prints DIVERGED instead of them and
	 * `swba run` exits 3; summary.json and ape.csv keep them, flagged. */
	bool diverged = false;
	std::string divergence;  ///< why, one line
	/** The median squared whitened innovation of the row's readings over its χ² median (1: as the
	 * declared noise predicts); empty when not measured (no landmark estimates). */
	std::optional<double> reading_misfit;

	bool failed = false;
	std::size_t failed_step = 0;  ///< the step k whose processing threw
	std::string failure;          ///< one line
	/** Stopped by RunControl::stop_requested (failed is set too: no APE; failed_step = the steps done,
	 * 0 for a row that never started). */
	bool interrupted = false;
};

/** Everything a run produced. */
struct RunReport
{
	std::string rawlog, ground_truth;  ///< ground_truth "" = none found (no APE)
	std::size_t steps = 0;             ///< steps run
	std::size_t distinct_landmarks = 0, readings = 0, skipped_readings = 0;
	std::size_t readings_with_own_noise = 0;  ///< readings with their own covariance (validCovariances)
	std::vector<RunRow> rows;
	std::vector<std::string> files;    ///< files written (full paths), in writing order
	std::vector<std::string> notes;    ///< one line each (plot notes, reader warnings, …)
	std::string time_label = "t = step k + 1";  ///< what the rows' time stamps are (x axis of the plots over time)
};

/** How a caller steers a long run: `stop_requested` is polled between steps (window, EKF) and before
 * each estimator (batch and causal run to their end once started); when it returns true the running
 * estimator's rows and every one not yet started are marked interrupted. `row_done` is called with
 * the report so far each time an estimator's rows are complete. Both optional. */
struct RunControl
{
	std::function<bool()> stop_requested;
	std::function<void(const RunReport&)> row_done;
};

/** Runs every estimator the options ask for on `rawlog` (already read) and fills the rows; APE when
 * `ground_truth` is not empty. Progress lines go to `log` (when options.progress). Writes no file. */
RunReport run_estimators(const RunOptions& options, const io::Rawlog& rawlog,
						 const std::vector<mrpt::poses::CPose3D>& ground_truth, std::ostream& log,
						 const RunControl& control = {});

/** The comparison table (one row per estimator; failures with their step and message). */
std::string format_comparison_table(const RunReport& report);
/** The note of a row with RunRow::association: "<label>: association P % correct (…), L landmarks for T
 * true, D duplicate, S spurious[, R re-associated in the window, A ambiguous on arrival]" (stderr of swba run
 * and swba merge; ReadingCounts::ambiguous). */
std::string format_association_note(const RunRow& row);
/** ape.txt: per estimator a header line and evo's blocks (APE translation part, full transformation,
 * rotation angle; RPE translation part between consecutive steps). */
std::string format_ape_text(const RunReport& report);
/** ape.csv: header + one row per estimator (translation and full-transformation statistics). */
std::string format_ape_csv(const RunReport& report);
/** summary.json (see doc/run.md for the shape). */
std::string format_summary_json(const RunReport& report);

/** Writes the TUM files, ape.txt, ape.csv, summary.json and config.ini of the rows so far (no plots)
 * and records them in report.files. Throws std::runtime_error naming a path that cannot be written. */
void write_run_files(const RunOptions& options, const std::vector<mrpt::poses::CPose3D>& ground_truth,
					 RunReport& report);

/** Writes the output directory (TUM files, ape.txt, ape.csv, summary.json, config.ini, plots) and
 * records the paths in report.files. Throws std::runtime_error naming a path that cannot be written. */
void write_run_outputs(const RunOptions& options, const std::vector<mrpt::poses::CPose3D>& ground_truth,
					   RunReport& report);

/** True when the report has rows and every one of them failed (swba run then exits 1). */
bool every_estimator_failed(const RunReport& report);
/** True when some row is marked diverged, or failed (not interrupted). */
bool some_estimator_failed_or_diverged(const RunReport& report);

/** True when a row was interrupted (RunControl::stop_requested). */
bool run_interrupted(const RunReport& report);

/** The whole `swba run`: reads the rawlog (options.rawlog must be set) and the ground truth, runs,
 * prints the table to `out`, writes the files; notes and progress go to `log`. The output files
 * (TUM trajectories, ape.txt/csv, summary.json) are rewritten as each estimator completes, so an
 * interrupted run keeps what was complete. Throws on bad input (one-line messages naming the
 * file/option). */
RunReport run_app(const RunOptions& options, std::ostream& out, std::ostream& log,
				  const std::function<bool()>& stop_requested = {});
}  // namespace swba::apps
