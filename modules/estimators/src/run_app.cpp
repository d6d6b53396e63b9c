// swba run: the estimators on one rawlog (EKF, window per W/policy/FEJ, batch, causal) and the APE.
#include <swba/estimators/ekf_slam.h>
#include <swba/estimators/run_app.h>
#include <swba/estimators/sliding_window.h>
#include <swba/eval/evaluation.h>
#include <swba/eval/trajectory.h>

#include <mrpt/system/filesystem.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <stdexcept>

namespace swba::estimators
{
namespace
{
using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

/** A progress line on `log` for a task that runs longer than a second: on a terminal one line
 * rewritten in place ("\r"), otherwise a line every 10 s. */
class ProgressLine
{
   public:
	ProgressLine(std::ostream& log, bool enabled, std::string label, std::size_t total)
		: log_(log), enabled_(enabled), label_(std::move(label)), total_(total), start_(Clock::now()), last_(start_)
	{
		tty_ = (&log == &std::cerr) && ::isatty(2);
	}
	~ProgressLine() { finish(); }
	void update(std::size_t done)
	{
		if (!enabled_) return;
		const auto now = Clock::now();
		const double since_start = std::chrono::duration<double>(now - start_).count();
		const double since_last = std::chrono::duration<double>(now - last_).count();
		if (since_start < 1.0 || (printed_ && since_last < (tty_ ? 0.25 : 10.0))) return;
		last_ = now;
		printed_ = true;
		char buf[64];
		std::snprintf(buf, sizeof(buf), " (%.1f s)", since_start);
		const std::string text = label_ + ": step " + std::to_string(done) + "/" + std::to_string(total_) + buf;
		if (tty_)
			log_ << "\r" << text << "\x1b[K" << std::flush;
		else
			log_ << text << "\n" << std::flush;
	}
	/** Announces a single long task (no steps): printed at once. */
	void announce(const std::string& what)
	{
		if (!enabled_) return;
		log_ << label_ << ": " << what << (tty_ ? "" : "\n") << std::flush;
		printed_ = true;
		announced_ = true;
	}
	void finish()
	{
		if (!enabled_ || finished_) return;
		finished_ = true;
		if (!printed_) return;
		char buf[64];
		std::snprintf(buf, sizeof(buf), "%.1f s", seconds_since(start_));
		if (tty_)
			log_ << "\r" << label_ << ": done in " << buf << "\x1b[K\n" << std::flush;
		else
			log_ << label_ << ": done in " << buf << "\n" << std::flush;
		(void)announced_;
	}

   private:
	std::ostream& log_;
	bool enabled_;
	std::string label_;
	std::size_t total_;
	Clock::time_point start_, last_;
	bool tty_ = false, printed_ = false, finished_ = false, announced_ = false;
};

std::string one_line(const std::string& what)
{
	std::string s = io::mrpt_exception_summary(what);
	for (auto& c : s)
		if (c == '\n' || c == '\r') c = ' ';
	return s;
}

/** The estimates after the steps (t ≥ 1): a trajectory that also holds the start pose (t = 0, fixed
 * by the gauge) loses it, so that every estimator is compared over the same poses. */
eval::Trajectory after_steps(const eval::Trajectory& t)
{
	eval::Trajectory out;
	for (std::size_t i = 0; i < t.size(); i++)
		if (t.stamps[i] >= 0.5) out.push_back(t.stamps[i], t.poses[i]);
	return out;
}

void compute_row_ape(RunRow& row, const std::vector<mrpt::poses::CPose3D>& gt)
{
	if (gt.empty() || row.failed || row.estimate.empty()) return;
	const auto [trans, full] = ape_against_ground_truth(gt, row.estimate);
	row.ape_trans = trans;
	row.ape_full = full;
	row.has_ape = true;
}

std::string fej_name(bool fej) { return fej ? "fej" : "nofej"; }
}  // namespace

// ----------------------------------------------------------------------------------------------
std::string default_ground_truth_path(const std::string& rawlog_path)
{
	std::string base = rawlog_path;
	for (const char* ext : {".rawlog.gz", ".rawlog"})
	{
		const std::string e = ext;
		if (base.size() > e.size() && base.compare(base.size() - e.size(), e.size(), e) == 0)
		{
			base.resize(base.size() - e.size());
			break;
		}
	}
	return base + "_ground_truth_robot_path.txt";
}

std::vector<mrpt::poses::CPose3D> read_ground_truth_for(const std::string& path, std::size_t steps)
{
	const std::vector<mrpt::poses::CPose3D> rows = eval::read_mrpt_ground_truth(path).poses;
	if (rows.size() < steps + 1)
		throw std::runtime_error("ground truth '" + path + "': " + std::to_string(rows.size()) +
								 " rows, but the rawlog has " + std::to_string(steps) + " steps and needs " +
								 std::to_string(steps + 1) +
								 " rows (row i = true pose at SF_i; the estimate after step k pairs with row k+1)");
	return rows;
}

eval::Trajectory ground_truth_trajectory(const std::vector<mrpt::poses::CPose3D>& rows)
{
	eval::Trajectory t;
	for (std::size_t i = 0; i < rows.size(); i++) t.push_back(static_cast<double>(i), rows[i]);
	return t;
}

eval::Trajectory paired_ground_truth(const std::vector<mrpt::poses::CPose3D>& rows, const eval::Trajectory& estimate)
{
	eval::Trajectory ref;
	for (std::size_t i = 0; i < estimate.size(); i++)
	{
		const double t = estimate.stamps[i];
		const double r = std::round(t);
		if (!(std::abs(t - r) < 1e-9) || r < 1)
			throw std::runtime_error("estimate pose " + std::to_string(i) + " has time " + std::to_string(t) +
									 ", not a step time k + 1 >= 1");
		const auto row = static_cast<std::size_t>(r);
		if (row >= rows.size())
			throw std::runtime_error("estimate at t = " + std::to_string(row) + " has no ground-truth row " +
									 std::to_string(row) + " (" + std::to_string(rows.size()) + " rows)");
		ref.push_back(t, rows[row]);
	}
	return ref;
}

std::pair<eval::Statistics, eval::Statistics> ape_against_ground_truth(
	const std::vector<mrpt::poses::CPose3D>& rows, const eval::Trajectory& estimate)
{
	const auto ref = paired_ground_truth(rows, estimate);
	std::vector<double> trans = eval::ape_errors(ref, estimate, eval::PoseRelation::TranslationPart);
	std::vector<double> full = eval::ape_errors(ref, estimate, eval::PoseRelation::FullTransformation);
	return {eval::compute_statistics(trans), eval::compute_statistics(full)};
}

// ----------------------------------------------------------------------------------------------
RunReport run_estimators(const RunOptions& options, const io::Rawlog& rawlog,
						 const std::vector<mrpt::poses::CPose3D>& gt, std::ostream& log)
{
	options.validate();
	RunReport report;
	report.rawlog = rawlog.path;
	report.steps = rawlog.steps.size();
	report.distinct_landmarks = rawlog.distinct_landmarks;
	report.readings = rawlog.readings;
	report.skipped_readings = rawlog.skipped_readings;
	const std::size_t n = rawlog.steps.size();
	if (n == 0) throw std::runtime_error("rawlog '" + rawlog.path + "': no steps");

	SlidingWindowOptions base = options.window;
	base.solver.num_threads = options.threads;

	// --- MRPT's EKF, each method.
	if (options.run_ekf)
	{
		constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;
		for (const auto& method : options.ekf_methods)
		{
			RunRow row;
			row.name = "ekf";
			row.method = method;
			row.label = "ekf " + method;
			row.trajectory = "online";
			EkfSlamOptions eo;
			eo.method = method;
			eo.ini_file = options.ekf_ini;
			// The same sensor noise as the window: the option if set, else the observation's own
			// (given explicitly, so that an EKF INI's std_sensor_* cannot differ from the window's).
			const io::RawlogStep* with_obs = nullptr;
			for (const auto& st : rawlog.steps)
				if (st.has_observation)
				{
					with_obs = &st;
					break;
				}
			auto noise = [&](double option, double observed, double scale, std::optional<double>& dst) {
				if (option > 0)
					dst = option * scale;
				else if (with_obs && observed > 0)
					dst = observed * scale;
			};
			noise(base.sensor_std_range, with_obs ? with_obs->sensor_std_range : 0, 1.0, eo.std_range_m);
			noise(base.sensor_std_yaw, with_obs ? with_obs->sensor_std_yaw : 0, kRadToDeg, eo.std_yaw_deg);
			noise(base.sensor_std_pitch, with_obs ? with_obs->sensor_std_pitch : 0, kRadToDeg, eo.std_pitch_deg);
			ProgressLine progress(log, options.progress, row.label, n);
			auto last = Clock::now();
			eo.progress = [&](std::size_t done, std::size_t) {
				const auto now = Clock::now();
				row.step_ms.push_back(std::chrono::duration<double, std::milli>(now - last).count());
				last = now;
				progress.update(done);
			};
			EkfSlamResult res;
			try
			{
				res = run_ekf_slam(rawlog.steps, eo);
			}
			catch (const std::exception& e)
			{
				// Bad EKF options (e.g. a missing EKF INI) are the user's error, not an EKF failure.
				throw std::runtime_error("EKF " + method + ": " + one_line(e.what()));
			}
			progress.finish();
			for (std::size_t i = 0; i < res.poses.size(); i++) row.estimate.push_back(res.times[i], res.poses[i]);
			row.seconds = res.seconds;
			row.steps = res.steps_processed;
			row.ms_per_step = res.ms_per_step;
			if (res.failed)
			{
				row.failed = true;
				row.failed_step = res.failed_step;
				row.failure = res.failure;
			}
			if (!res.notes.empty()) report.notes.push_back(row.label + ": " + res.notes);
			if (res.mrpt_warnings)
				report.notes.push_back(row.label + ": " + std::to_string(res.mrpt_warnings) + " MRPT warnings, first: " +
									   one_line(res.first_mrpt_warning));
			compute_row_ape(row, gt);
			report.rows.push_back(std::move(row));
		}
	}

	// --- The window, for each policy × FEJ × W: online and lagged rows.
	const bool combos = options.policies.size() * options.fej.size() > 1;
	for (const auto policy : options.policies)
		for (const bool fej : options.fej)
			for (const int W : options.windows)
			{
				SlidingWindowOptions wo = base;
				wo.window_size = W;
				wo.policy = policy;
				wo.first_estimate_jacobians = fej;
				RunRow online;
				online.name = "window";
				online.window = W;
				online.policy = to_string(policy);
				online.fej = fej;
				online.trajectory = "online";
				const std::string suffix = combos ? " " + online.policy + " " + fej_name(fej) : "";
				const std::string file_suffix = combos ? "_" + online.policy + "_" + fej_name(fej) : "";
				online.label = "window W=" + std::to_string(W) + suffix;
				online.file = "window_" + std::to_string(W) + file_suffix + ".tum";
				RunRow lagged = online;
				lagged.trajectory = "lagged";
				lagged.label = online.label + " lagged";
				lagged.file = "window_" + std::to_string(W) + file_suffix + "_lagged.tum";

				ProgressLine progress(log, options.progress, online.label, n);
				double total = 0;
				std::size_t done = 0;
				double iterations = 0;
				try
				{
					SlidingWindowEstimator est(wo);
					for (const auto& step : rawlog.steps)
					{
						const auto t0 = Clock::now();
						const StepSummary& s = est.process(step);
						const double dt = seconds_since(t0);
						total += dt;
						iterations += s.iterations;
						online.step_ms.push_back(dt * 1e3);
						progress.update(++done);
					}
					const auto t0 = Clock::now();
					est.finish();
					total += seconds_since(t0);
					online.step_summaries = est.step_summaries();
					online.estimate = after_steps(est.online_trajectory());
					lagged.estimate = after_steps(est.lagged_trajectory());
				}
				catch (const std::exception& e)
				{
					for (RunRow* r : {&online, &lagged})
					{
						r->failed = true;
						r->failed_step = done;
						r->failure = one_line(e.what());
					}
				}
				progress.finish();
				for (RunRow* r : {&online, &lagged})
				{
					r->seconds = total;
					r->steps = done;
					r->ms_per_step = done ? total * 1e3 / static_cast<double>(done) : 0.0;
					r->mean_iterations = done ? iterations / static_cast<double>(done) : 0.0;
					compute_row_ape(*r, gt);
				}
				lagged.step_ms = online.step_ms;
				report.rows.push_back(std::move(online));
				report.rows.push_back(std::move(lagged));
			}

	SlidingWindowOptions unbounded = base;
	unbounded.window_size = 0;
	unbounded.policy = options.policies.front();
	unbounded.first_estimate_jacobians = options.fej.front();

	// --- Batch: all factors, one solve.
	if (options.run_batch)
	{
		RunRow row;
		row.name = "batch";
		row.label = "batch";
		row.trajectory = "smoothed";
		row.file = "batch.tum";
		ProgressLine progress(log, options.progress, row.label, n);
		if (n > 300) progress.announce("solving all " + std::to_string(n) + " steps at once...");
		const auto t0 = Clock::now();
		try
		{
			BatchResult b = run_batch(rawlog, unbounded, options.batch_max_iterations);
			row.estimate = after_steps(b.trajectory);
			row.mean_iterations = b.summary.iterations;
			if (!b.summary.is_solution_usable())
			{
				row.failed = true;
				row.failed_step = n;
				row.failure = "batch solve failed: " + b.summary.message;
			}
		}
		catch (const std::exception& e)
		{
			row.failed = true;
			row.failed_step = n;
			row.failure = one_line(e.what());
		}
		row.seconds = seconds_since(t0);
		progress.finish();
		row.steps = n;
		row.ms_per_step = row.seconds * 1e3 / static_cast<double>(n);
		compute_row_ape(row, gt);
		report.rows.push_back(std::move(row));
	}

	// --- The full-history causal optimum ("online, W = ∞").
	if (options.run_causal)
	{
		RunRow row;
		row.name = "causal";
		row.label = "causal (online W=inf)";
		row.trajectory = "online";
		row.file = "causal.tum";
		ProgressLine progress(log, options.progress, row.label, n);
		progress.announce("re-solving the whole history after each of " + std::to_string(n) + " steps...");
		const auto t0 = Clock::now();
		try
		{
			row.estimate = after_steps(run_full_history_causal(rawlog, unbounded));
		}
		catch (const std::exception& e)
		{
			row.failed = true;
			row.failed_step = n;
			row.failure = one_line(e.what());
		}
		row.seconds = seconds_since(t0);
		progress.finish();
		row.steps = n;
		row.ms_per_step = row.seconds * 1e3 / static_cast<double>(n);
		compute_row_ape(row, gt);
		report.rows.push_back(std::move(row));
	}

	// EKF file names: ekf.tum for one method, ekf_<method>.tum for several.
	std::size_t ekf_rows = 0;
	for (const auto& r : report.rows) ekf_rows += r.name == "ekf";
	for (auto& r : report.rows)
		if (r.name == "ekf") r.file = ekf_rows == 1 ? "ekf.tum" : "ekf_" + r.method + ".tum";
	return report;
}

// ----------------------------------------------------------------------------------------------
RunReport run_app(const RunOptions& options, std::ostream& out, std::ostream& log)
{
	if (options.rawlog.empty()) throw std::invalid_argument("no rawlog given");
	options.validate();

	io::RawlogReaderOptions ro;
	ro.max_steps = options.max_steps;
	const io::Rawlog rawlog = io::read_rawlog(options.rawlog, ro);

	std::string gt_path = options.ground_truth;
	if (gt_path.empty())
	{
		const std::string guess = default_ground_truth_path(options.rawlog);
		if (mrpt::system::fileExists(guess)) gt_path = guess;
	}
	std::vector<mrpt::poses::CPose3D> gt;
	if (!gt_path.empty()) gt = read_ground_truth_for(gt_path, rawlog.steps.size());

	log << "swba run: " << rawlog.path << ": " << rawlog.steps.size() << " steps, " << rawlog.distinct_landmarks
		<< " landmarks, " << rawlog.readings << " readings";
	if (rawlog.skipped_readings) log << " (" << rawlog.skipped_readings << " invalid readings skipped)";
	log << "\n";
	if (gt_path.empty())
		log << "swba run: no ground truth (" << default_ground_truth_path(options.rawlog)
			<< " not found; give --gt FILE): no APE\n";
	else
		log << "swba run: ground truth " << gt_path << "\n";
	for (const auto& w : rawlog.warnings) log << "warning: " << w << "\n";
	if (rawlog.warning_count > rawlog.warnings.size())
		log << "warning: ... " << (rawlog.warning_count - rawlog.warnings.size()) << " more warnings\n";

	RunReport report = run_estimators(options, rawlog, gt, log);
	report.ground_truth = gt_path;
	write_run_outputs(options, gt, report, log);
	out << format_comparison_table(report) << std::flush;
	for (const auto& note : report.notes) log << "note: " << note << "\n";
	log << "swba run: wrote " << report.files.size() << " files into " << options.out_dir << "/\n";
	return report;
}
}  // namespace swba::estimators
