// Reading a job's summary.json back (internal to the sweep apps; the writer is run/report.cpp).
#pragma once

#include <swba/apps/run.h>
#include <swba/apps/sweep.h>

#include <nlohmann/json.hpp>

#include <iosfwd>
#include <string>
#include <vector>

namespace swba::apps
{
/** The JSON of the sweep sources (summaries, the manifest): nlohmann's, keeping the keys in the order
 * they are written. */
using nlohmann::ordered_json;

/** A job's summary.json. */
struct JobSummary
{
	std::string dir;   ///< the job's output directory
	std::string path;  ///< <dir>/summary.json
	ordered_json json;
};

/** check_jobs_complete, keeping what it read: every job's summary.json, parsed once (job K at K - 1),
 * each a complete summary of its kind (range-bearing: an "estimators" array; inertial: "rows"). */
std::vector<JobSummary> read_complete_jobs(const SweepPlan& plan, std::ostream& log);

/** Before merging: throws std::invalid_argument "not a <what> sweep" unless `plan` is of `kind`, then
 * read_complete_jobs. */
std::vector<JobSummary> check_mergeable(const SweepPlan& plan, SweepKind kind, const std::string& what,
										std::ostream& log);

/** One "estimators" entry as a RunRow: names, statistics (exactly the doubles written), times,
 * failure; the estimate read from its TUM file in `dir` when the file exists. Throws
 * std::runtime_error naming `source` on a missing or mistyped field. */
RunRow run_row_from_json(const ordered_json& entry, const std::string& dir, const std::string& source);

/** The covariance file of a TUM file: same stem, ".cov" (window_30.tum → window_30.cov). */
std::string covariance_file_name(const std::string& tum_file);

/** The covariance file of `row` in `dir`: <TUM stem>.cov, or for an EKF row written as ekf.tum (one
 * method) also ekf_<method>.cov; "" when neither exists. */
std::string find_covariance_file(const std::string& dir, const RunRow& row);
}  // namespace swba::apps
