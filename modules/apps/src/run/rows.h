// swba run: one function per kind of estimator row (internal to the run app).
#pragma once

#include <swba/apps/run.h>

#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

namespace swba::apps
{
/** What every row runner needs: the rawlog, the ground truth (empty = no APE), the log. */
struct RowContext
{
	const RunOptions& options;
	const io::Rawlog& rawlog;
	const std::vector<mrpt::poses::CPose3D>& ground_truth;
	std::ostream& log;
	/** The window/batch options with the run's thread count. */
	estimators::SlidingWindowOptions base;
	/** RunControl::stop_requested (may be empty). */
	std::function<bool()> stop = {};

	bool stopped() const { return stop && stop(); }
};

/** The `failure` text of an interrupted row. */
inline constexpr const char* kInterrupted = "interrupted";
/** Marks `row` interrupted after `steps_done` steps. */
void mark_interrupted(RunRow& row, std::size_t steps_done);

/** MRPT's EKF with `method`: one row; its notes (MRPT warnings) are appended to `notes`. Throws
 * std::runtime_error on bad EKF options (a user error, unlike an EKF failure, which is a failed row). */
RunRow run_ekf_row(const RowContext& ctx, const std::string& method, std::vector<std::string>& notes);
/** The window with `options`: its online and lagged rows. `combos`: the labels name policy and FEJ. */
std::pair<RunRow, RunRow> run_window_rows(const RowContext& ctx, const estimators::SlidingWindowOptions& options,
										  bool combos);
/** The batch solution (window = ∞, one solve), started from dead reckoning, or from `start` (a window's
 * lagged trajectory, described by `start_name`, e.g. "lagged W=30"). */
RunRow run_batch_row(const RowContext& ctx, const estimators::SlidingWindowOptions& unbounded,
					 const eval::Trajectory* start = nullptr, const std::string& start_name = "dead reckoning");
/** The full-history causal optimum ("online, W = ∞"). */
RunRow run_causal_row(const RowContext& ctx, const estimators::SlidingWindowOptions& unbounded);

/** A multi-line exception text (MRPT's carry a call stack) as one line. */
std::string one_line(const std::string& what);
/** Fills row.ape_* from the ground truth (nothing for a failed row or without ground truth), and row.nees
 * (compute_row_nees). */
void compute_row_ape(RunRow& row, const std::vector<mrpt::poses::CPose3D>& ground_truth);
/** Fills row.nees from row.covariance (one per pose of row.estimate; nothing without) and the ground
 * truth, or row.nees_error when a covariance is not positive definite. */
void compute_row_nees(RunRow& row, const std::vector<mrpt::poses::CPose3D>& ground_truth);
}  // namespace swba::apps
