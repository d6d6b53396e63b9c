// swba run: read the rawlog and ground truth, run every estimator asked for, report.
#include "../report_helpers.h"
#include "divergence.h"
#include "output_dir.h"
#include "rows.h"

#include <swba/apps/inertial_run.h>
#include <swba/apps/run.h>
#include <swba/eval/ground_truth.h>

#include <mrpt/system/filesystem.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <ostream>
#include <stdexcept>

namespace swba::apps
{
namespace
{
RunReport empty_report(const io::Rawlog& rawlog)
{
	RunReport report;
	report.rawlog = rawlog.path;
	report.steps = rawlog.steps.size();
	report.distinct_landmarks = rawlog.distinct_landmarks;
	report.readings = rawlog.readings;
	report.skipped_readings = rawlog.skipped_readings;
	report.readings_with_own_noise = rawlog.readings_with_own_noise;
	if (report.steps == 0) throw std::runtime_error("rawlog '" + rawlog.path + "': no steps");
	return report;
}

/** A note when the window's marginalisation dropped factors it could not evaluate (their information
 * is lost). */
void note_unevaluable_factors(const RunRow& online, std::vector<std::string>& notes)
{
	long total = 0, steps = 0;
	for (const auto& s : online.step_summaries)
		if (s.unevaluable_factors > 0)
		{
			total += s.unevaluable_factors;
			steps++;
		}
	if (total > 0)
		notes.push_back(online.label + ": " + std::to_string(total) + " factors could not be evaluated when marginalised (at " +
						std::to_string(steps) + " steps) and were dropped: their information is lost");
}

/** Map policy: how many landmarks re-entered from the map, and a note for those whose marginal could
 * not be kept (forgotten, as the constant-time policy does). */
void note_map(const RunRow& online, std::vector<std::string>& notes)
{
	long returned = 0, lost = 0;
	for (const auto& s : online.step_summaries)
	{
		returned += s.landmarks_from_map;
		lost += s.landmarks_not_mapped;
	}
	if (returned > 0) notes.push_back(online.label + ": " + std::to_string(returned) + " landmarks re-entered from the map");
	if (lost > 0)
		notes.push_back(online.label + ": " + std::to_string(lost) +
						" landmarks left the window without a usable covariance and were not kept in the map");
}

/** The window for each policy × FEJ × W: online and lagged rows. */
void add_window_rows(const RowContext& ctx, RunReport& report, const RunControl& control)
{
	const RunOptions& options = ctx.options;
	const bool combos = options.policies.size() * options.fej.size() > 1;
	for (const auto policy : options.policies)
		for (const bool fej : options.fej)
			for (const int W : options.windows)
			{
				estimators::SlidingWindowOptions wo = ctx.base;
				wo.window_size = W;
				wo.policy = policy;
				wo.first_estimate_jacobians = fej;
				auto [online, lagged] = run_window_rows(ctx, wo, combos);
				note_unevaluable_factors(online, report.notes);
				if (policy == estimators::LandmarkPolicy::Map) note_map(online, report.notes);
				report.rows.push_back(std::move(online));
				report.rows.push_back(std::move(lagged));
				if (control.row_done) control.row_done(report);
			}
}

/** EKF file names: ekf.tum for one method, ekf_<method>.tum for several. */
void name_ekf_files(RunReport& report, std::size_t methods)
{
	for (auto& r : report.rows)
		if (r.name == "ekf") r.file = methods == 1 ? "ekf.tum" : "ekf_" + r.method + ".tum";
}

void print_inputs(const RunOptions& options, const io::Rawlog& rawlog, const std::string& gt_path, std::ostream& log)
{
	log << "swba run: " << rawlog.path << ": " << rawlog.steps.size() << " steps, ";
	if (rawlog.distinct_landmarks == 0 && rawlog.readings > 0)
		log << "no landmark IDs (data association: " << enum_name(options.window.association) << "), ";
	else
		log << rawlog.distinct_landmarks << " landmarks, ";
	log << rawlog.readings << " readings";
	if (rawlog.skipped_readings) log << " (" << rawlog.skipped_readings << " invalid readings skipped)";
	if (rawlog.readings_with_own_noise)
		log << ", " << rawlog.readings_with_own_noise << " with their own covariance (validCovariances: their noise "
			<< "unless --sensor-std-* / [sensor] set one)";
	log << "\n";
	if (gt_path.empty())
		log << "swba run: no ground truth (" << eval::default_ground_truth_path(options.rawlog)
			<< " not found; give --gt FILE): no APE\n";
	else
		log << "swba run: ground truth " << gt_path << "\n";
	if (estimators::resolve_pose_model(options.window.model, rawlog.steps) == estimators::PoseModel::Planar)
		log << "swba run: planar rawlog (2D odometry, readings without pitch): 2D model, MRPT's CRangeBearingKFSLAM2D\n";
	else if (io::is_planar(rawlog.steps))
		log << "swba run: planar rawlog (2D odometry, readings without pitch) run with the 6D model ([window] model "
			   "= 6d), MRPT's CRangeBearingKFSLAM\n";
	for (const auto& w : rawlog.warnings) log << "warning: " << w << "\n";
	if (rawlog.warning_count > rawlog.warnings.size())
		log << "warning: ... " << (rawlog.warning_count - rawlog.warnings.size()) << " more warnings\n";
}

/** Auto: data association (JCBB) when some reading has no landmark ID, else the IDs. */
estimators::DataAssociation resolve_association(estimators::DataAssociation a, const io::Rawlog& rawlog)
{
	if (a != estimators::DataAssociation::Auto) return a;
	for (const auto& st : rawlog.steps)
		for (const auto& r : st.readings)
			if (r.landmark_id < 0) return estimators::DataAssociation::Jcbb;
	return estimators::DataAssociation::Ids;
}

/** The landmark IDs of `path`, a rawlog with the same readings as `rawlog` in the same order (throws
 * std::runtime_error naming the file and the first step that differs, or the first reading without an ID). */
estimators::ReadingIds ids_from_rawlog(const std::string& path, const io::Rawlog& rawlog)
{
	io::RawlogReaderOptions ro;
	ro.max_steps = rawlog.steps.size();
	ro.require_landmark_ids = false;  // a reading without one is named below, as this file's fault
	const io::Rawlog truth = io::read_rawlog(path, ro);
	const std::string what = "association truth '" + path + "': ";
	if (truth.steps.size() != rawlog.steps.size())
		throw std::runtime_error(what + std::to_string(truth.steps.size()) + " steps, the rawlog has " +
								 std::to_string(rawlog.steps.size()));
	for (std::size_t k = 0; k < truth.steps.size(); k++)
	{
		const auto& a = truth.steps[k].readings;
		const auto& b = rawlog.steps[k].readings;
		bool same = a.size() == b.size();
		for (std::size_t i = 0; same && i < a.size(); i++)
		{
			same = a[i].range == b[i].range && a[i].yaw == b[i].yaw;
			if (same && a[i].landmark_id < 0)
				throw std::runtime_error(what + "step " + std::to_string(k) + ", reading " + std::to_string(i) +
										 " has no landmark ID: the truth must be the rawlog with its IDs");
		}
		if (!same) throw std::runtime_error(what + "step " + std::to_string(k) + " does not hold the rawlog's readings");
	}
	return estimators::reading_ids(truth);
}

/** The truth of the readings' landmarks and where it comes from (ids empty: unknown). */
struct AssociationTruth
{
	estimators::ReadingIds ids;
	std::string source;
};

/** The truth of the readings' landmarks: --association-truth's IDs; else the readings' own IDs when every
 * reading has one; else the simulator's landmark ground truth next to the rawlog with the robot path.
 * Read before any estimator runs, so that a bad truth file fails at once. */
AssociationTruth read_association_truth(const io::Rawlog& rawlog, const RunOptions& options,
										const std::vector<mrpt::poses::CPose3D>& gt)
{
	if (!options.association_truth.empty())
		return {ids_from_rawlog(options.association_truth, rawlog), options.association_truth + " (its landmark IDs)"};
	bool all_ids = true;
	for (const auto& st : rawlog.steps)
		for (const auto& r : st.readings) all_ids = all_ids && r.landmark_id >= 0;
	if (all_ids) return {estimators::reading_ids(rawlog), "the rawlog's landmark IDs"};
	const std::string path = eval::default_landmarks_path(options.rawlog);
	if (gt.empty() || !mrpt::system::fileExists(path)) return {};
	// Landmarks are points a few metres apart in simulated maps; a reading's point lies within a few
	// sensor sigmas of its landmark. 0.5 m leaves a reading of no landmark unmatched.
	return {estimators::true_landmarks_of_readings(rawlog, gt, estimators::read_landmark_ground_truth(path), 0.5),
			path};
}

/** Association quality of every row with assigned IDs, as a note per estimator. */
void add_association_quality(RunReport& report, const AssociationTruth& truth, const RunOptions& options,
							 std::ostream& log)
{
	if (truth.ids.empty())
	{
		report.notes.push_back("data association (" + std::string(enum_name(options.window.association)) +
							   "): no ground truth of the landmarks found, quality not measured");
		return;
	}
	log << "swba run: association quality against " << truth.source << "\n";
	for (auto& r : report.rows)
	{
		if (r.assigned_ids.empty() || r.failed) continue;
		r.association = estimators::evaluate_association(r.assigned_ids, truth.ids);
		if (r.trajectory != "lagged") report.notes.push_back(format_association_note(r));
	}
}

/** The lagged row of the widest window that finished, or nullptr. */
const RunRow* widest_lagged(const RunReport& report)
{
	const RunRow* best = nullptr;
	for (const auto& r : report.rows)
		if (r.name == "window" && r.trajectory == "lagged" && !r.failed && !r.estimate.empty() &&
			(!best || r.window > best->window))
			best = &r;
	return best;
}

/** The batch from dead reckoning and, when a window ran, from the widest window's lagged trajectory:
 * the start with the lower final cost (the same objective) is the batch row, the other is reported as
 * batch_alt. Dead reckoning over a real log can leave the batch in a local minimum; a start that is
 * already close to the solution does not depend on it. */
void add_batch_rows(const RowContext& ctx, const estimators::SlidingWindowOptions& unbounded, RunReport& report)
{
	RunRow dr = run_batch_row(ctx, unbounded);
	const RunRow* lagged = widest_lagged(report);
	if (!lagged)
	{
		report.rows.push_back(std::move(dr));
		return;
	}
	const std::string w = std::to_string(lagged->window);
	RunRow lg = run_batch_row(ctx, unbounded, &lagged->estimate, "lagged W=" + w);
	const bool lagged_better = !lg.failed && (dr.failed || lg.final_cost.value_or(INFINITY) < dr.final_cost.value_or(INFINITY));
	RunRow& chosen = lagged_better ? lg : dr;
	RunRow& other = lagged_better ? dr : lg;
	const auto short_start = [&](const RunRow& r) { return &r == &lg ? "W=" + w + " start" : std::string("DR start"); };
	chosen.label = "batch (" + short_start(chosen) + ")";
	other.name = "batch_alt";
	other.label = "batch alt (" + short_start(other) + ")";
	other.file = "batch_alt.tum";
	// Six digits, or nine when six print the two costs alike (then they differ further down, or not at all).
	const double a = chosen.final_cost.value_or(NAN), b = other.final_cost.value_or(NAN);
	char pa[32], pb[32], buf[240];
	for (const int digits : {6, 9})
	{
		std::snprintf(pa, sizeof pa, "%.*g", digits, a);
		std::snprintf(pb, sizeof pb, "%.*g", digits, b);
		if (std::string(pa) != pb) break;
	}
	std::snprintf(buf, sizeof buf, "batch: started from %s (final cost %s), %s from %s (%s): the batch row",
				  chosen.start.c_str(), pa, std::string(pa) == pb ? "the same as" : "lower than", other.start.c_str(), pb);
	report.notes.push_back(other.failed ? "batch: started from " + chosen.start + "; from " + other.start + " it failed"
										: std::string(buf));
	report.rows.push_back(std::move(chosen));
	report.rows.push_back(std::move(other));
}

/** `rawlog` with the landmark IDs `ids` (by step and reading); readings `ids` does not cover (a window
 * run that stopped early) get IDs of their own. */
io::Rawlog with_landmark_ids(const io::Rawlog& rawlog, const estimators::ReadingIds& ids)
{
	io::Rawlog out = rawlog;
	std::int32_t next = 0;
	for (const auto& step : ids)
		for (std::int32_t id : step) next = std::max(next, id + 1);
	for (std::size_t k = 0; k < out.steps.size(); k++)
		for (std::size_t i = 0; i < out.steps[k].readings.size(); i++)
			out.steps[k].readings[i].landmark_id = k < ids.size() && i < ids[k].size() ? ids[k][i] : next++;
	return out;
}

/** One note per estimator on what the χ² gate and the robust loss did (lagged rows share their online
 * row's run). */
void add_reading_notes(RunReport& report)
{
	for (const auto& r : report.rows)
	{
		if (!r.reading_counts || r.trajectory == "lagged" || r.failed) continue;
		const auto& c = *r.reading_counts;
		report.notes.push_back(r.label + ": " + std::to_string(c.readings) + " readings, " + std::to_string(c.gated) +
							   " gated (" + std::to_string(c.readmitted) + " re-admitted), " +
							   std::to_string(c.unconfirmed) + " unconfirmed first readings, " +
							   std::to_string(c.excluded) + " never used, " + std::to_string(c.down_weighted) +
							   " down-weighted" +
							   (c.young_held_steps > 0 ? "; young landmarks' readings kept re-linearised on " +
															 std::to_string(c.young_held_steps) + " steps"
													   : std::string()) +
							   (c.association_cut > 0 ? "; JCBB's search cut at its node budget on " +
															std::to_string(c.association_cut) +
															" steps (the best pairing found so far kept)"
													  : std::string()));
	}
}

/** One note per estimator with a covariance and ground truth (not diverged) on the consistency of that
 * covariance. */
void add_nees_notes(RunReport& report)
{
	char buf[256];
	for (const auto& r : report.rows)
	{
		if (!r.nees_error.empty()) report.notes.push_back(r.label + ": NEES not computed: " + r.nees_error);
		if (!r.nees || r.diverged) continue;  // a diverged row's figures are not a result
		const RowNees& n = *r.nees;
		std::snprintf(buf, sizeof(buf),
					  "NEES against the ground truth (%zu poses): position %.2f (%d dof), pose %.2f (%d dof); %.1f %% / "
					  "%.1f %% inside one run's 95 %% band (about 95 %% if the covariance is consistent)",
					  n.poses, n.position_mean, n.position_dof, n.pose_mean, n.pose_dof, 100.0 * n.position_in_band,
					  100.0 * n.pose_in_band);
		report.notes.push_back(r.label + ": " + buf);
	}
}
}  // namespace

RunReport run_estimators(const RunOptions& options, const io::Rawlog& rawlog,
						 const std::vector<mrpt::poses::CPose3D>& gt, std::ostream& log, const RunControl& control)
{
	options.validate();
	RunReport report = empty_report(rawlog);
	RowContext ctx{options, rawlog, gt, log, options.window, control.stop_requested};
	const auto done = [&] {
		if (control.row_done) control.row_done(report);
	};

	if (options.run_ekf)
		for (const auto& method : options.ekf_methods)
		{
			report.rows.push_back(run_ekf_row(ctx, method, report.notes));
			done();
		}
	add_window_rows(ctx, report, control);

	estimators::SlidingWindowOptions unbounded = ctx.base;
	unbounded.window_size = 0;
	unbounded.policy = options.policies.front();
	unbounded.first_estimate_jacobians = options.fej.front();
	// With data association, the batch and causal rows take the last window run's decisions (a copy:
	// the rows vector grows below).
	estimators::ReadingIds decided;
	if (ctx.base.association != estimators::DataAssociation::Ids)
		for (const auto& r : report.rows)
			if (r.name == "window" && !r.failed && !r.assigned_ids.empty()) decided = r.assigned_ids;
	std::optional<io::Rawlog> relabelled;
	if (!decided.empty())
	{
		relabelled = with_landmark_ids(rawlog, decided);
		unbounded.association = estimators::DataAssociation::Ids;
	}
	const RowContext unbounded_ctx{options, relabelled ? *relabelled : rawlog, gt, log, ctx.base, control.stop_requested};
	if (options.run_batch)
	{
		add_batch_rows(unbounded_ctx, unbounded, report);
		for (auto& r : report.rows)
			if (r.name == "batch" || r.name == "batch_alt") r.assigned_ids = decided;
		done();
	}
	if (options.run_causal) report.rows.push_back(run_causal_row(unbounded_ctx, unbounded));
	if (options.run_causal) report.rows.back().assigned_ids = decided;
	name_ekf_files(report, options.ekf_methods.size());
	add_reading_notes(report);
	mark_diverged_rows(report, rawlog, ctx.base,
					   estimators::resolve_pose_model(ctx.base.model, rawlog.steps) == estimators::PoseModel::Planar);
	add_nees_notes(report);
	return report;
}

std::string format_association_note(const RunRow& r)
{
	if (!r.association) return "";
	const auto& q = *r.association;
	char buf[256];
	std::snprintf(buf, sizeof buf,
				  "%s: association %.2f %% correct (%zu of %zu associated readings right, %zu of %zu readings "
				  "associated), %zu landmarks for %zu true, %zu duplicate, %zu spurious",
				  r.label.c_str(), 100.0 * q.fraction_correct(), q.correct, q.associated, q.associated, q.readings,
				  q.landmarks, q.true_landmarks, q.duplicates, q.spurious);
	std::string note = buf;
	if (r.name == "window" && r.reading_counts)
		note += ", " + std::to_string(r.reading_counts->reassociated) + " re-associated in the window, " +
				std::to_string(r.reading_counts->ambiguous) + " ambiguous on arrival, " +
				std::to_string(r.reading_counts->rematched) + " matched with the pose's covariance inflated";
	return note;
}

bool run_interrupted(const RunReport& report)
{
	for (const auto& r : report.rows)
		if (r.interrupted) return true;
	return false;
}

bool some_estimator_failed_or_diverged(const RunReport& report)
{
	for (const auto& r : report.rows)
		if (r.diverged || (r.failed && !r.interrupted)) return true;
	return false;
}

bool every_estimator_failed(const RunReport& report)
{
	for (const auto& r : report.rows)
		if (!r.failed) return false;
	return !report.rows.empty();
}

RunReport run_app(const RunOptions& given, std::ostream& out, std::ostream& log,
				  const std::function<bool()>& stop_requested)
{
	if (given.rawlog.empty()) throw std::invalid_argument("no rawlog given");
	given.validate();
	if (io::is_observation_rawlog(given.rawlog)) return run_inertial_app(given, out, log, stop_requested);

	io::RawlogReaderOptions ro;
	ro.max_steps = given.max_steps;
	ro.require_landmark_ids = given.window.association == estimators::DataAssociation::Ids;
	const io::Rawlog rawlog = io::read_rawlog(given.rawlog, ro);
	if (given.window.model == estimators::PoseModel::Planar && !io::is_planar(rawlog.steps))
		throw std::runtime_error("rawlog '" + given.rawlog + "' is not planar (3D odometry or readings with pitch): "
								 "[window] model = 2d needs a planar rawlog (auto or 6d reads this one)");
	RunOptions options = given;
	options.window.association = resolve_association(given.window.association, rawlog);

	std::string gt_path = options.ground_truth;
	if (gt_path.empty())
	{
		const std::string guess = eval::default_ground_truth_path(options.rawlog);
		if (mrpt::system::fileExists(guess)) gt_path = guess;
	}
	std::vector<mrpt::poses::CPose3D> gt;
	if (!gt_path.empty()) gt = eval::read_ground_truth_for(gt_path, rawlog.steps.size());
	// A rawlog cut short (a plain, uncompressed rawlog truncated at an object boundary reads as a
	// complete shorter one) shows only here: the ground truth outlives it.
	if (!options.max_steps && gt.size() > rawlog.steps.size() + 1)
		log << "swba run: warning: the ground truth has " << gt.size() << " rows but the rawlog only "
			<< rawlog.steps.size() << " steps (" << rawlog.steps.size() + 1
			<< " rows used): is the rawlog cut short, or the ground truth another run's?\n";
	print_inputs(options, rawlog, gt_path, log);
	const bool associating = options.window.association != estimators::DataAssociation::Ids;
	const AssociationTruth truth = associating ? read_association_truth(rawlog, options, gt) : AssociationTruth{};
	prepare_output_directory(options.out_dir, "swba run", log);

	RunControl control;
	control.stop_requested = stop_requested;
	control.row_done = [&](const RunReport& so_far) {
		// What is complete is on disk at once: TUM files, ape.txt/csv and summary.json so far.
		RunReport snapshot = so_far;
		snapshot.ground_truth = gt_path;
		name_ekf_files(snapshot, options.ekf_methods.size());
		write_run_files(options, gt, snapshot);
	};
	RunReport report = run_estimators(options, rawlog, gt, log, control);
	report.ground_truth = gt_path;
	if (associating) add_association_quality(report, truth, options, log);
	write_run_outputs(options, gt, report);
	out << format_comparison_table(report) << std::flush;
	for (const auto& note : report.notes) log << "note: " << note << "\n";
	detail::print_wrote_files(log, "swba run", report.files.size(), options.out_dir);
	return report;
}
}  // namespace swba::apps
