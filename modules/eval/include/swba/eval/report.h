/** \file report.h
 * Reports of evaluation results: evo's text block, CSV and JSON (statistics and per-pose errors).
 * All output is deterministic (fixed formats, no time stamps). */
#pragma once

#include <iosfwd>
#include <string>
#include <utility>
#include <vector>

#include "swba/eval/evaluation.h"
#include "swba/eval/metrics.h"

namespace swba::eval
{
/** evo's Result.pretty_str(): `title`, a blank line, then one line per statistic in name order,
 * formatted as Python's "{:>10}\t{:.6f}\n", e.g. "       max\t0.066243\n". */
std::string format_statistics_text(const std::string& title, const Statistics& stats);
/** format_statistics_text(result.title, result.stats) — what `swba ape` prints. */
std::string format_text_report(const MetricResult& result);

/** The text of <m>_stats.json, one JSON object of statistics:
 * {"max":…,"mean":…,"median":…,"min":…,"rmse":…,"sse":…,"std":…,"count":n}
 * with 2-space indentation and no final newline. Numbers are the shortest text that reads back as the
 * same double; a non-finite value is written as null. */
std::string statistics_json(const Statistics& stats);
/** Writes statistics_json(stats) to `path` (+ newline); throws std::runtime_error naming the path. */
void write_statistics_json(const std::string& path, const Statistics& stats);

/** The text of <m>_result.json (layout and numbers as statistics_json): metric, title, relation, unit,
 * alignment (flags, scale, rotation, translation, origin transform), input/associated pose counts,
 * "stats" (as statistics_json) and the per-pose arrays "stamps" and "errors". */
std::string result_json(const MetricResult& result);

/** Per-pose errors as CSV, header `t,error,ref_x,ref_y,ref_z,est_x,est_y,est_z` (estimate after
 * alignment; for RPE the row's pose is the second pose of the pair). */
void write_errors_csv(std::ostream& out, const MetricResult& result);

/** Statistics table as CSV, header `name,count,max,mean,median,min,rmse,sse,std`, one row per
 * (name, statistics) — e.g. one row per estimator. Names containing `,` or `"` are quoted. */
void write_statistics_csv(std::ostream& out, const std::vector<std::pair<std::string, Statistics>>& rows);

/** Writes into `dir` (created if missing): <prefix>_stats.json, <prefix>_stats.csv,
 * <prefix>_errors.csv, <prefix>_result.json, <prefix>_est_aligned.tum, where prefix defaults to the
 * metric in lower case ("ape"/"rpe"). Returns the written paths; throws std::runtime_error naming
 * the path on an I/O failure. */
std::vector<std::string> save_results(const MetricResult& result, const std::string& dir,
									  const std::string& prefix = "");
}  // namespace swba::eval
