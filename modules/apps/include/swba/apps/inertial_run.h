/** \file inertial_run.h
 * `swba run` on an inertial rawlog (observation format, detected from its content by run_app): the
 * error-state Kalman filter, the dead-reckoning rows (IMU only; odometry only), the inertial window for
 * each W (online and lagged), the batch solution and optionally the full-history causal optimum, scored
 * against the ground truth by time stamp (APE translation and rotation angle, not aligned: the priors fix
 * the frame) with the position NEES of the rows that carry covariances. Writes <label>.tum per row,
 * ape.txt and summary.json into options.out_dir (doc/inertial.md). */
#pragma once

#include <swba/apps/run.h>
#include <swba/apps/run_options.h>

#include <functional>
#include <iosfwd>
#include <string>

namespace swba::apps
{
/** The ground truth of an inertial rawlog: options.ground_truth (TUM) if given, else
 * <rawlog without extension>_ground_truth.tum next to it if it exists, else "". */
std::string inertial_ground_truth_path(const RunOptions& options);

/** Runs the inertial estimators (see the file comment); the table goes to `out`, progress and notes to
 * `log`. `stop_requested` (optional; run_app's) is polled before each estimator: once it returns true, that
 * estimator's rows and every later one's are marked interrupted (RunRow::interrupted, "INTERRUPTED after 0
 * steps" in the table, "interrupted": true and no file in summary.json); an estimator runs to its end once
 * started. A row whose estimate matches only some of its poses to the ground truth gets a note (how many of
 * how many). Throws std::runtime_error, before any estimator runs, naming the rawlog and the keyframe when
 * two consecutive keyframes have no IMU reading between them, and naming the ground truth and both time
 * ranges when none of its stamps matches a keyframe; and naming the file that cannot be written. */
RunReport run_inertial_app(const RunOptions& options, std::ostream& out, std::ostream& log,
						   const std::function<bool()>& stop_requested = {});
}  // namespace swba::apps
