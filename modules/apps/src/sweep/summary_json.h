// Reading a job's summary.json back (internal to the sweep apps; the writer is run/report.cpp).
#pragma once

#include <swba/apps/run.h>
#include <swba/apps/sweep.h>

#include <nlohmann/json.hpp>

#include <iosfwd>
#include <string>

namespace swba::apps
{
/** A job's summary.json. */
struct JobSummary
{
	std::string dir;   ///< the job's output directory
	std::string path;  ///< <dir>/summary.json
	nlohmann::ordered_json json;
};

/** Before merging: throws std::invalid_argument "not a <what> sweep" unless `plan` is of `kind`, then
 * check_jobs_complete. */
void check_mergeable(const SweepPlan& plan, SweepKind kind, const std::string& what, std::ostream& log);

/** Reads <dir>/summary.json. Throws std::runtime_error naming the file (missing, not JSON, no
 * "estimators"). */
JobSummary read_job_summary(const std::string& dir);

/** One "estimators" entry as a RunRow: names, statistics (exactly the doubles written), times,
 * failure; the estimate read from its TUM file in `dir` when the file exists. Throws
 * std::runtime_error naming `source` on a missing or mistyped field. */
RunRow run_row_from_json(const nlohmann::ordered_json& entry, const std::string& dir, const std::string& source);

/** The covariance file of a TUM file: same stem, ".cov" (window_30.tum → window_30.cov). */
std::string covariance_file_name(const std::string& tum_file);

/** The covariance file of `row` in `dir`: <TUM stem>.cov, or for an EKF row written as ekf.tum (one
 * method) also ekf_<method>.cov; "" when neither exists. */
std::string find_covariance_file(const std::string& dir, const RunRow& row);
}  // namespace swba::apps
