// swba run: the EKF, window, batch and causal rows.
#include "rows.h"

#include "covariance_files.h"
#include "progress.h"

#include <swba/estimators/ekf_slam.h>
#include <swba/estimators/sliding_window.h>
#include <swba/eval/ground_truth.h>
#include <swba/eval/nees.h>

#include <cstdio>
#include <optional>
#include <ostream>
#include <stdexcept>
#include <utility>

namespace swba::apps
{
namespace
{

/** The estimates after the steps (t ≥ 1): a trajectory that also holds the start pose (t = 0, fixed
 * by the gauge) loses it, so that every estimator is compared over the same poses. */
eval::Trajectory after_steps(const eval::Trajectory& t)
{
	eval::Trajectory out;
	for (std::size_t i = 0; i < t.size(); i++)
		if (t.stamps[i] >= 0.5) out.push_back(t.stamps[i], t.poses[i]);
	return out;
}

/** The covariances of the poses after_steps(t) keeps (`c` parallel to `t`; empty stays empty). */
std::vector<estimators::PoseCovariance> after_steps(const eval::Trajectory& t,
													const std::vector<estimators::PoseCovariance>& c)
{
	std::vector<estimators::PoseCovariance> out;
	if (c.size() != t.size()) return out;
	for (std::size_t i = 0; i < t.size(); i++)
		if (t.stamps[i] >= 0.5) out.push_back(c[i]);
	return out;
}

/** Under the free gauge nothing holds the initial pose at the origin, so the estimate is in a frame of
 * its own: expressed relative to the estimator's own estimate of the initial pose (T₀⁻¹·T_k), it is
 * in the frame the fixed gauge holds (initial pose = origin) and comparable with the other rows.
 * Other gauges: unchanged. A pose covariance (right perturbation) is unchanged by that change of
 * frame; landmark_frame() moves the landmarks with it. */
eval::Trajectory in_gauge_frame(eval::Trajectory t, const estimators::SlidingWindowOptions& o,
								const mrpt::poses::CPose3D& initial)
{
	if (o.gauge != GaugeMode::Free) return t;
	for (auto& p : t.poses) p = p - initial;
	return t;
}

/** The landmarks in the frame of in_gauge_frame: p ← R₀ᵀ(p − t₀), Σ ← R₀ᵀ Σ R₀ under the free gauge. */
std::map<std::int32_t, estimators::LandmarkEstimate> landmark_frame(std::map<std::int32_t, estimators::LandmarkEstimate> l,
																	const estimators::SlidingWindowOptions& o,
																	const mrpt::poses::CPose3D& initial)
{
	if (o.gauge != GaugeMode::Free) return l;
	const Eigen::Matrix3d Rt = initial.getRotationMatrix().asEigen().transpose();
	const Eigen::Vector3d t(initial.x(), initial.y(), initial.z());
	for (auto& [id, e] : l)
	{
		e.position = Rt * (e.position - t);
		e.covariance = Rt * e.covariance * Rt.transpose();
	}
	return l;
}

std::string fej_name(bool fej) { return fej ? "fej" : "nofej"; }

/** The EKF's sensor noise: the window's option if set, else the observation's own (given explicitly,
 * so that an EKF INI's std_sensor_* cannot differ from the window's). */
void set_ekf_sensor_noise(const RowContext& ctx, estimators::EkfSlamOptions& eo)
{
	const io::RawlogStep* with_obs = nullptr;
	for (const auto& st : ctx.rawlog.steps)
		if (st.has_observation)
		{
			with_obs = &st;
			break;
		}
	auto noise = [&](double option, double observed, std::optional<double>& dst) {
		if (option > 0)
			dst = option;
		else if (with_obs && observed > 0)
			dst = observed;
	};
	const estimators::SensorNoiseOptions& s = ctx.base.sensor;
	noise(s.std_range, with_obs ? with_obs->sensor_std_range : 0, eo.std_range);
	noise(s.std_yaw, with_obs ? with_obs->sensor_std_yaw : 0, eo.std_yaw);
	noise(s.std_pitch, with_obs ? with_obs->sensor_std_pitch : 0, eo.std_pitch);
}

/** --verbose: one line per window step (its solve, the state it left). */
void log_step_summary(std::ostream& log, const std::string& label, const estimators::StepSummary& s, double seconds)
{
	char buf[320];
	std::snprintf(buf, sizeof(buf),
				  "%s step %zu: LM %d it, cost %.6g -> %.6g, %s (%s); %d poses, %d landmarks, prior rank %d; "
				  "solve %.2f ms, marginalisation %.2f ms, covariance %.2f ms, step %.2f ms\n",
				  label.c_str(), s.step, s.iterations, s.initial_cost, s.final_cost, to_string(s.termination),
				  s.solver_message.c_str(), s.window_poses, s.landmarks, s.prior_rank, s.solve_seconds * 1e3,
				  s.marginalization_seconds * 1e3, s.covariance_seconds * 1e3, seconds * 1e3);
	log << buf << std::flush;
}

/** A row whose single task (batch, causal) failed at the end of the run. */
void mark_failed(RunRow& row, std::size_t step, const std::string& why)
{
	row.failed = true;
	row.failed_step = step;
	row.failure = why;
}

}  // namespace

RunRow::RunRow(std::string name, std::string label, std::string trajectory, int window)
	: name(std::move(name)), label(std::move(label)), window(window), trajectory(std::move(trajectory))
{
}

void mark_interrupted(RunRow& row, std::size_t steps_done)
{
	row.failed = true;
	row.interrupted = true;
	row.failed_step = steps_done;
	row.failure = kInterrupted;
	row.has_ape = false;
}

std::string one_line(const std::string& what)
{
	std::string s = io::mrpt_exception_summary(what);
	for (auto& c : s)
		if (c == '\n' || c == '\r') c = ' ';
	return s;
}

void compute_row_nees(RunRow& row, const std::vector<mrpt::poses::CPose3D>& gt)
{
	if (row.covariance.empty() || row.covariance.size() != row.estimate.size()) return;
	std::vector<eval::CovarianceRow> cov;
	for (std::size_t i = 0; i < row.covariance.size(); i++)
	{
		eval::CovarianceRow c;
		c.stamp = row.estimate.stamps[i];
		c.position = world_position_covariance(row.estimate.poses[i], row.covariance[i]);
		c.pose = row.covariance[i];
		cov.push_back(c);
	}
	try
	{
		const eval::RunNees run = eval::run_nees(row.estimate, cov, gt, row.label);
		if (run.position.empty()) return;
		const eval::AverageNees a = eval::average_nees({run});
		RowNees n;
		n.poses = run.position.size();
		n.position_mean = a.position.mean_over_steps;
		n.pose_mean = a.pose.mean_over_steps;
		n.position_dof = run.position.front().dof;
		n.pose_dof = run.pose.front().dof;
		n.position_in_band = a.position.share_in_band;
		n.pose_in_band = a.pose.share_in_band;
		row.nees = n;
	}
	catch (const std::exception& e)
	{
		row.nees_error = one_line(e.what());
	}
}

void compute_row_ape(RunRow& row, const std::vector<mrpt::poses::CPose3D>& gt)
{
	if (gt.empty() || row.failed || row.estimate.empty()) return;
	row.ape_trans_errors =
		eval::ape_errors_against_ground_truth(gt, row.estimate, eval::PoseRelation::TranslationPart);
	row.ape_trans = eval::compute_statistics(row.ape_trans_errors);
	row.ape_full = eval::compute_statistics(
		eval::ape_errors_against_ground_truth(gt, row.estimate, eval::PoseRelation::FullTransformation));
	row.ape_rot = eval::compute_statistics(
		eval::ape_errors_against_ground_truth(gt, row.estimate, eval::PoseRelation::RotationAngleDeg));
	row.has_ape = true;
	compute_row_nees(row, gt);
	row.has_rpe = row.estimate.size() >= 2;
	if (row.has_rpe)
		row.rpe_trans = eval::compute_statistics(eval::rpe_errors(eval::paired_ground_truth(gt, row.estimate), row.estimate,
																	eval::PoseRelation::TranslationPart,
																	eval::rpe_pairs(row.estimate.size(), 1, false)));
}

RunRow run_ekf_row(const RowContext& ctx, const std::string& method, std::vector<std::string>& notes)
{
	RunRow row("ekf", "ekf " + method, "online");
	row.method = method;
	estimators::EkfSlamOptions eo;
	eo.method = method;
	eo.ini_file = ctx.options.ekf_ini;
	eo.model = ctx.base.model;
	if (ctx.base.association == estimators::DataAssociation::NearestNeighbour) eo.data_association = "nn";
	if (ctx.base.association == estimators::DataAssociation::Jcbb) eo.data_association = "jcbb";
	set_ekf_sensor_noise(ctx, eo);
	ProgressLine progress(ctx.log, ctx.options.progress, row.label, ctx.rawlog.steps.size());
	auto last = SteadyClock::now();
	std::size_t steps_done = 0;
	eo.progress = [&](std::size_t done, std::size_t) {
		if (ctx.stopped()) throw std::runtime_error(kInterrupted);  // the filter reports it as its failure
		steps_done = done;
		const auto now = SteadyClock::now();
		row.step_ms.push_back(std::chrono::duration<double, std::milli>(now - last).count());
		last = now;
		progress.update(done);
	};
	estimators::EkfSlamResult res;
	try
	{
		res = estimators::run_ekf_slam(ctx.rawlog.steps, eo);
	}
	catch (const std::exception& e)
	{
		if (!ctx.stopped()) throw std::runtime_error("EKF " + method + ": " + one_line(e.what()));
		res.failed = true;  // stopped where the filter does not catch (its set-up): no estimate to keep
		res.failed_step = steps_done;
	}
	progress.finish();
	for (std::size_t i = 0; i < res.poses.size(); i++) row.estimate.push_back(res.times[i], res.poses[i]);
	row.covariance = res.covariances;
	row.landmarks = res.landmarks_final;
	// With data association, its decisions are compared with the truth like the window's.
	if (ctx.base.association != estimators::DataAssociation::Ids) row.assigned_ids = res.assigned_ids;
	row.seconds = res.seconds;
	row.steps = res.steps_processed;
	row.ms_per_step = res.ms_per_step;
	if (res.failed) mark_failed(row, res.failed_step, res.failure);
	if (res.failed && ctx.stopped()) mark_interrupted(row, res.failed_step);
	if (res.model == estimators::PoseModel::Planar)
		notes.push_back(row.label + ": MRPT's 2D filter CRangeBearingKFSLAM2D (planar rawlog)");
	if (!res.notes.empty()) notes.push_back(row.label + ": " + res.notes);
	if (res.mrpt_warnings)
		notes.push_back(row.label + ": " + std::to_string(res.mrpt_warnings) + " MRPT warnings, first: " +
						one_line(res.first_mrpt_warning));
	compute_row_ape(row, ctx.ground_truth);
	return row;
}

namespace
{
/** The online row of a window run, named after W (and policy/FEJ when several are run). */
RunRow window_row(const estimators::SlidingWindowOptions& wo, bool combos)
{
	RunRow online;
	online.name = "window";
	online.window = wo.window_size;
	online.policy = to_string(wo.policy);
	online.fej = wo.first_estimate_jacobians;
	online.trajectory = "online";
	const std::string W = std::to_string(wo.window_size);
	const std::string fej = fej_name(wo.first_estimate_jacobians);
	const std::string suffix = combos ? " " + online.policy + " " + fej : "";
	const std::string file_suffix = combos ? "_" + online.policy + "_" + fej : "";
	online.label = "window W=" + W + suffix;
	online.file = "window_" + W + file_suffix + ".tum";
	return online;
}

/** The lagged row beside an online one (same window, its own label and file). */
RunRow lagged_row(const RunRow& online)
{
	RunRow lagged = online;
	lagged.trajectory = "lagged";
	lagged.label = online.label + " lagged";
	lagged.file = online.file.substr(0, online.file.size() - 4) + "_lagged.tum";
	return lagged;
}

/** After the last step: the window finished (its time added to `total`), both trajectories in the
 * gauge's frame, the readings and associations, and with wo.covariances the covariances and the
 * landmark map (the map's time added to `total` and, with every step's, to covariance_seconds). */
void collect_window_results(estimators::SlidingWindowEstimator& est, const estimators::SlidingWindowOptions& wo,
							RunRow& online, RunRow& lagged, double& total)
{
	const auto t0 = SteadyClock::now();
	est.finish();
	total += seconds_since(t0);
	online.step_summaries = est.step_summaries();
	online.reading_counts = lagged.reading_counts = est.reading_counts();
	online.assigned_ids = lagged.assigned_ids = est.assigned_ids();
	online.estimate = after_steps(in_gauge_frame(est.online_trajectory(), wo, est.initial_pose()));
	lagged.estimate = after_steps(in_gauge_frame(est.lagged_trajectory(), wo, est.initial_pose()));
	if (!wo.covariances) return;
	online.covariance = after_steps(est.online_trajectory(), est.online_covariances());
	lagged.covariance = after_steps(est.lagged_trajectory(), est.lagged_covariances());
	const auto t1 = SteadyClock::now();
	online.landmarks = lagged.landmarks = landmark_frame(est.landmark_estimates(), wo, est.initial_pose());
	double cov_seconds = seconds_since(t1);
	for (const auto& s : est.step_summaries()) cov_seconds += s.covariance_seconds;
	total += seconds_since(t1);
	online.covariance_seconds = lagged.covariance_seconds = cov_seconds;
}
}  // namespace

std::pair<RunRow, RunRow> run_window_rows(const RowContext& ctx, const estimators::SlidingWindowOptions& wo,
										  bool combos)
{
	RunRow online = window_row(wo, combos);
	RunRow lagged = lagged_row(online);
	ProgressLine progress(ctx.log, ctx.options.progress, online.label, ctx.rawlog.steps.size());
	double total = 0, iterations = 0;
	std::size_t done = 0;
	try
	{
		estimators::SlidingWindowEstimator est(wo);
		for (const auto& step : ctx.rawlog.steps)
		{
			if (ctx.stopped()) break;
			const auto t0 = SteadyClock::now();
			const estimators::StepSummary& s = est.process(step);
			const double dt = seconds_since(t0);
			if (ctx.options.verbose) log_step_summary(ctx.log, online.label, s, dt);
			total += dt;
			iterations += s.iterations;
			online.step_ms.push_back(dt * 1e3);
			progress.update(++done);
		}
		collect_window_results(est, wo, online, lagged, total);
	}
	catch (const std::exception& e)
	{
		for (RunRow* r : {&online, &lagged}) mark_failed(*r, done, one_line(e.what()));
	}
	progress.finish();
	if (done < ctx.rawlog.steps.size() && !online.failed)
		for (RunRow* r : {&online, &lagged}) mark_interrupted(*r, done);
	for (RunRow* r : {&online, &lagged})
	{
		r->seconds = total;
		r->steps = done;
		r->ms_per_step = done ? total * 1e3 / static_cast<double>(done) : 0.0;
		r->mean_iterations = done ? iterations / static_cast<double>(done) : 0.0;
		compute_row_ape(*r, ctx.ground_truth);
	}
	lagged.step_ms = online.step_ms;
	return {std::move(online), std::move(lagged)};
}

namespace
{
/** A row computed by one task over all steps (batch, causal): `task` fills the estimate and may mark
 * the row failed; an exception from it fails the row at the last step. */
template <class Task>
RunRow single_task_row(const RowContext& ctx, RunRow row, const std::string& announcement, bool announce, Task task)
{
	const std::size_t n = ctx.rawlog.steps.size();
	ProgressLine progress(ctx.log, ctx.options.progress, row.label, n);
	if (ctx.stopped())
	{
		mark_interrupted(row, 0);  // never started: a batch or causal solve cannot stop half-way
		return row;
	}
	if (announce) progress.announce(announcement);
	const auto t0 = SteadyClock::now();
	try
	{
		task(row);
	}
	catch (const estimators::StepError& e)
	{
		mark_failed(row, e.step(), one_line(e.what()));
	}
	catch (const std::exception& e)
	{
		mark_failed(row, n, one_line(e.what()));
	}
	progress.finish();
	row.seconds = seconds_since(t0);
	row.steps = n;
	row.ms_per_step = row.seconds * 1e3 / static_cast<double>(n);
	compute_row_ape(row, ctx.ground_truth);
	return row;
}

RunRow named_row(const std::string& name, const std::string& label, const std::string& trajectory)
{
	RunRow row(name, label, trajectory);
	row.file = name + ".tum";
	return row;
}
}  // namespace

RunRow run_batch_row(const RowContext& ctx, const estimators::SlidingWindowOptions& unbounded,
					 const eval::Trajectory* start, const std::string& start_name)
{
	const std::size_t n = ctx.rawlog.steps.size();
	RunRow named = named_row("batch", "batch", "smoothed");
	named.start = start_name;
	return single_task_row(ctx, std::move(named),
						   "solving all " + std::to_string(n) + " steps at once (from " + start_name + ")...", n > 300,
						   [&](RunRow& row) {
							   estimators::BatchResult b = estimators::run_batch(
								   ctx.rawlog, unbounded, ctx.options.batch_max_iterations, start);
							   row.final_cost = b.summary.final_cost;
							   row.estimate = after_steps(in_gauge_frame(b.trajectory, unbounded, b.initial_pose));
							   if (unbounded.covariances)
							   {
								   row.covariance = after_steps(b.trajectory, b.covariances);
								   row.landmarks = landmark_frame(b.landmarks, unbounded, b.initial_pose);
								   row.covariance_seconds = b.covariance_seconds;
							   }
							   row.mean_iterations = b.summary.iterations;
							   row.reading_counts = b.counts;
							   if (ctx.options.verbose)
								   ctx.log << "batch: " << b.rounds << " solve round(s); the last:\n"
										   << b.summary.full_report() << std::flush;
							   if (!b.summary.is_solution_usable())
								   mark_failed(row, n, "batch solve failed: " + b.summary.message);
						   });
}

RunRow run_causal_row(const RowContext& ctx, const estimators::SlidingWindowOptions& unbounded)
{
	const std::size_t n = ctx.rawlog.steps.size();
	return single_task_row(ctx, named_row("causal", "causal (online W=inf)", "online"),
						   "re-solving the whole history after each of " + std::to_string(n) + " steps...", true,
						   [&](RunRow& row) {
							   estimators::ReadingCounts counts;
							   mrpt::poses::CPose3D initial;
							   const eval::Trajectory t =
								   estimators::run_full_history_causal(ctx.rawlog, unbounded, &counts, &initial);
							   row.estimate = after_steps(in_gauge_frame(t, unbounded, initial));
							   row.reading_counts = counts;
						   });
}
}  // namespace swba::apps
