// swba run: read the rawlog and ground truth, run every estimator asked for, report.
#include "rows.h"

#include <swba/apps/run.h>
#include <swba/eval/ground_truth.h>

#include <mrpt/system/filesystem.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <ostream>
#include <stdexcept>
#include <unistd.h>

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
	log << "swba run: " << rawlog.path << ": " << rawlog.steps.size() << " steps, " << rawlog.distinct_landmarks
		<< " landmarks, " << rawlog.readings << " readings";
	if (rawlog.skipped_readings) log << " (" << rawlog.skipped_readings << " invalid readings skipped)";
	log << "\n";
	if (gt_path.empty())
		log << "swba run: no ground truth (" << eval::default_ground_truth_path(options.rawlog)
			<< " not found; give --gt FILE): no APE\n";
	else
		log << "swba run: ground truth " << gt_path << "\n";
	if (io::is_planar(rawlog.steps))
		log << "swba run: planar rawlog (2D odometry, readings without pitch): 2D model, MRPT's CRangeBearingKFSLAM2D\n";
	for (const auto& w : rawlog.warnings) log << "warning: " << w << "\n";
	if (rawlog.warning_count > rawlog.warnings.size())
		log << "warning: ... " << (rawlog.warning_count - rawlog.warnings.size()) << " more warnings\n";
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
							   " down-weighted");
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
	if (options.run_batch) report.rows.push_back(run_batch_row(ctx, unbounded));
	if (options.run_batch) done();
	if (options.run_causal) report.rows.push_back(run_causal_row(ctx, unbounded));
	name_ekf_files(report, options.ekf_methods.size());
	add_reading_notes(report);
	return report;
}

/** Creates `dir` and checks that a file can be created in it: a run must not spend its estimation
 * time and then lose the results to a mistyped or read-only --out. */
void prepare_output_directory(const std::string& dir)
{
	std::error_code ec;
	if (std::filesystem::exists(dir, ec) && !std::filesystem::is_directory(dir, ec))
		throw std::runtime_error("output directory '" + dir + "' exists and is not a directory");
	std::filesystem::create_directories(dir, ec);
	if (ec) throw std::runtime_error("cannot create output directory '" + dir + "': " + ec.message());
	const std::string probe = dir + "/.swba_write_test." + std::to_string(::getpid());
	std::FILE* f = std::fopen(probe.c_str(), "w");
	if (!f) throw std::runtime_error("cannot write into output directory '" + dir + "': " + std::strerror(errno));
	std::fclose(f);
	std::remove(probe.c_str());
}

bool run_interrupted(const RunReport& report)
{
	for (const auto& r : report.rows)
		if (r.interrupted) return true;
	return false;
}

bool every_estimator_failed(const RunReport& report)
{
	for (const auto& r : report.rows)
		if (!r.failed) return false;
	return !report.rows.empty();
}

RunReport run_app(const RunOptions& options, std::ostream& out, std::ostream& log,
				  const std::function<bool()>& stop_requested)
{
	if (options.rawlog.empty()) throw std::invalid_argument("no rawlog given");
	options.validate();

	io::RawlogReaderOptions ro;
	ro.max_steps = options.max_steps;
	const io::Rawlog rawlog = io::read_rawlog(options.rawlog, ro);

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
	prepare_output_directory(options.out_dir);

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
	write_run_outputs(options, gt, report);
	out << format_comparison_table(report) << std::flush;
	for (const auto& note : report.notes) log << "note: " << note << "\n";
	log << "swba run: wrote " << report.files.size() << " files into " << options.out_dir << "/\n";
	return report;
}
}  // namespace swba::apps
