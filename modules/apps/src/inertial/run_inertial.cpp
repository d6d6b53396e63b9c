#include <swba/apps/inertial_run.h>

#include "../report_helpers.h"
#include "../run/output_dir.h"
#include "../run/plots.h"
#include "../run/rows.h"

#include <swba/core/chi2.h>
#include <swba/core/file.h>
#include <swba/estimators/inertial_window.h>
#include <swba/eval/association.h>
#include <swba/eval/metrics.h>
#include <swba/eval/nees.h>
#include <swba/eval/plot.h>
#include <swba/eval/trajectory.h>

#include <nlohmann/json.hpp>

#include <swba/core/timing.h>
#include <cmath>
#include <limits>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <map>
#include <optional>
#include <ostream>
#include <sstream>
#include <stdexcept>

namespace swba::apps
{
namespace fs = std::filesystem;

namespace
{
/** One row's extra figures (RunRow holds the APE). */
struct InertialFigures
{
	std::optional<eval::Statistics> rot_deg;
	std::optional<double> nees_mean, nees_inside;  ///< position NEES: mean, fraction in the 95 % band
	std::size_t matched = 0;  ///< poses of the row's estimate paired with a ground-truth pose (its APE's count)
};

/** Largest |Δt| at which an estimate and a ground-truth pose are paired, s: the rows report at the rawlog's
 * own pose times, which the ground truth of swba simulate-imu holds exactly. */
constexpr double kInertialGtMaxDiff = 1e-6;

/** "N poses, t = a .. b" of the stamps of `t` (time stamps as `swba ape` prints them). */
std::string inertial_time_range(const eval::Trajectory& t)
{
	std::ostringstream s;
	s << t.size() << " poses";
	if (!t.empty()) s << ", t = " << t.stamps.front() << " .. " << t.stamps.back();
	return s.str();
}

eval::Trajectory to_trajectory(const estimators::InertialTrajectory& t)
{
	eval::Trajectory out;
	for (std::size_t i = 0; i < t.t.size(); i++) out.push_back(t.t[i], t.poses[i]);
	return out;
}

/** APE (translation, rotation angle) and position NEES of `row` against the truth, paired by time. */
InertialFigures score(RunRow& row, const estimators::InertialTrajectory& est, const eval::Trajectory& gt)
{
	InertialFigures f;
	if (gt.empty() || est.t.empty()) return f;
	eval::AssociationOptions ao;
	ao.t_max_diff = kInertialGtMaxDiff;
	const eval::Association a = eval::associate(gt, row.estimate, ao);
	f.matched = a.size();
	if (a.size() == 0) return f;
	const eval::Trajectory ref = gt.subset(a.ref_ids), e = row.estimate.subset(a.est_ids);
	row.ape_trans_errors = eval::ape_errors(ref, e, eval::PoseRelation::TranslationPart);
	row.ape_trans = eval::compute_statistics(row.ape_trans_errors);
	row.ape_full = eval::compute_statistics(eval::ape_errors(ref, e, eval::PoseRelation::FullTransformation));
	f.rot_deg = eval::compute_statistics(eval::ape_errors(ref, e, eval::PoseRelation::RotationAngleDeg));
	row.has_ape = true;
	row.has_rpe = e.size() >= 2;  // as the range-bearing report: translation drift between consecutive keyframes
	if (row.has_rpe)
		row.rpe_trans = eval::compute_statistics(
			eval::rpe_errors(ref, e, eval::PoseRelation::TranslationPart, eval::rpe_pairs(e.size(), 1, false)));
	const double lo = chi2_quantile(0.025, 3), hi = chi2_quantile(0.975, 3);
	double sum = 0, inside = 0;
	std::size_t n = 0;
	for (std::size_t k = 0; k < a.size(); k++)
	{
		const Eigen::Matrix<double, 6, 6>& P = est.pose_covariances[a.est_ids[k]];
		if (P.topLeftCorner<3, 3>().isZero(0)) continue;
		const Eigen::VectorXd d = eval::pose_error_tangent(e.poses[k], ref.poses[k]).head<3>();
		const double v = eval::nees(d, P.topLeftCorner<3, 3>()).value;
		sum += v;
		inside += (v >= lo && v <= hi);
		n++;
	}
	if (n > 0)
	{
		f.nees_mean = sum / n;
		f.nees_inside = inside / n;
	}
	return f;
}

struct Rows
{
	std::vector<RunRow> rows;
	std::vector<InertialFigures> figures;
};

void add_row(Rows& r, const std::string& name, const std::string& label, int window, const std::string& trajectory,
			 const estimators::InertialTrajectory& est, double seconds, std::size_t steps, const eval::Trajectory& gt)
{
	RunRow row(name, label, trajectory, window);
	row.estimate = to_trajectory(est);
	row.seconds = seconds;
	row.steps = steps;
	row.ms_per_step = steps ? 1e3 * seconds / steps : 0;
	r.figures.push_back(score(row, est, gt));
	r.rows.push_back(std::move(row));
}

/** A row whose estimator did not run: the stop request came first (RunRow::interrupted, 0 steps). */
void add_interrupted_row(Rows& r, const std::string& name, const std::string& label, int window,
						 const std::string& trajectory)
{
	RunRow row(name, label, trajectory, window);
	mark_interrupted(row, 0);
	r.figures.emplace_back();
	r.rows.push_back(std::move(row));
}

double seconds_of(const std::function<void()>& f)
{
	const auto t0 = SteadyClock::now();
	f();
	return seconds_since(t0);
}

/** Runs estimators into rows, polling `stop` (may be empty) before each: once it has returned true,
 * that estimator's rows and every later one's are interrupted rows (an estimator runs to its end once
 * started). */
class RowRunner
{
   public:
	using Estimate = std::function<estimators::InertialTrajectory()>;
	using Steps = std::function<std::size_t(const estimators::InertialTrajectory&)>;

	RowRunner(Rows& r, const eval::Trajectory& gt, const std::function<bool()>& stop) : r_(r), gt_(gt), stop_(stop) {}

	/** False once the stop request has come (and from then on). */
	bool go() { return !(stopped_ = stopped_ || (stop_ && stop_())); }

	/** One row of a one-trajectory estimator; `steps` counts the steps its ms per step divides by. */
	void single(const std::string& name, const std::string& label, const std::string& trajectory, const Estimate& f,
				const Steps& steps)
	{
		if (!go())
			return add_interrupted_row(r_, name, label, 0, trajectory);
		estimators::InertialTrajectory t;
		const double s = seconds_of([&] { t = f(); });
		add_row(r_, name, label, 0, trajectory, t, s, steps(t), gt_);
	}

	Rows& rows() { return r_; }
	const eval::Trajectory& gt() const { return gt_; }

   private:
	Rows& r_;
	const eval::Trajectory& gt_;
	std::function<bool()> stop_;
	bool stopped_ = false;
};

/** The window rows (online and lagged) for every window size of `o`. */
void run_window_rows(const RunOptions& o, const estimators::InertialInput& in, estimators::InertialWindowOptions wo,
					 std::size_t keyframes, RowRunner& run, std::ostream& log)
{
	for (int W : o.windows)
	{
		wo.window_size = W;
		const std::string label = "window W=" + std::to_string(W);
		if (!run.go())
		{
			add_interrupted_row(run.rows(), "window", label, W, "online");
			add_interrupted_row(run.rows(), "window", label + " lagged", W, "lagged");
			continue;
		}
		estimators::InertialWindowResult w;
		const double s = seconds_of([&] { w = estimators::run_inertial_window(in, wo); });
		add_row(run.rows(), "window", label, W, "online", w.online, s, keyframes, run.gt());
		add_row(run.rows(), "window", label + " lagged", W, "lagged", w.lagged, s, keyframes, run.gt());
		if (o.progress) log << "swba run: " << label << " done (" << w.reintegrations << " re-integrations)\n";
	}
}

/** Runs the rows' estimators one after the other (RowRunner: the stop request between them). */
void run_rows(const RunOptions& o, const estimators::InertialInput& in, const eval::Trajectory& gt,
			  const std::function<bool()>& stop, Rows& r, std::ostream& log)
{
	estimators::InertialWindowOptions wo = o.inertial;
	wo.solver.num_threads = o.window.solver.num_threads;
	const std::vector<double> reports = estimators::inertial_report_times(in, wo.measurements.keyframes);
	const std::size_t kf = reports.size();
	const RowRunner::Steps imu_steps = [](const estimators::InertialTrajectory& t) { return t.imu_steps; };
	const RowRunner::Steps poses = [](const estimators::InertialTrajectory& t) { return t.t.size(); };
	const RowRunner::Steps keyframes = [kf](const estimators::InertialTrajectory&) { return kf; };
	RowRunner run(r, gt, stop);
	if (o.run_ekf)  // --no-ekf: the filter row is the ESKF's here
		run.single("eskf", "eskf", "online", [&] { return estimators::run_inertial_filter(in, wo.measurements); },
				   imu_steps);
	estimators::InertialFilterOptions dr = wo.measurements;
	dr.use_pose_priors = dr.use_odometry = false;
	run.single("imu-only", "imu only", "online", [&] { return estimators::run_inertial_filter(in, dr); }, imu_steps);
	if (!in.odometry.empty())
		run.single("odometry-only", "odometry only", "online",
				   [&] { return estimators::run_odometry_dead_reckoning(in, dr.prior, reports); }, poses);
	run_window_rows(o, in, wo, kf, run, log);
	if (o.run_batch)
		run.single("batch", "batch", "smoothed", [&] { return estimators::run_inertial_batch(in, wo); }, keyframes);
	if (o.run_causal)
	{
		wo.window_size = 0;
		run.single("causal", "causal", "online", [&] { return estimators::run_inertial_window(in, wo).online; },
				   keyframes);
	}
}

/** The notes of the rows whose estimate matched only some of its poses to the ground truth, one per
 * (matched, poses) count: "APE over M of N poses (…): <labels>". */
std::vector<std::string> partial_match_notes(const Rows& r, const std::string& gt_path, const eval::Trajectory& gt)
{
	std::map<std::pair<std::size_t, std::size_t>, std::string> labels;
	for (std::size_t i = 0; i < r.rows.size(); i++)
	{
		const RunRow& row = r.rows[i];
		if (gt.empty() || row.interrupted || row.estimate.empty() || r.figures[i].matched == row.estimate.size())
			continue;
		std::string& l = labels[{r.figures[i].matched, row.estimate.size()}];
		l += (l.empty() ? "" : ", ") + row.label;
	}
	std::vector<std::string> notes;
	for (const auto& [count, rows] : labels)
	{
		std::ostringstream s;
		s << "APE over " << count.first << " of " << count.second << " poses (the others have no pose of the ground truth '"
		  << gt_path << "' (" << inertial_time_range(gt) << ") within " << kInertialGtMaxDiff << " s of their time"
		  << (count.first == 0 ? ": no APE" : "") << "): " << rows;
		notes.push_back(s.str());
	}
	return notes;
}

std::string format_table(const Rows& r)
{
	std::ostringstream os;
	os << std::left << std::setw(22) << "estimator" << std::right << std::setw(12) << "APE RMSE m" << std::setw(12)
	   << "max m" << std::setw(12) << "RPE RMSE m" << std::setw(14) << "rot RMSE deg" << std::setw(11) << "pos NEES" << std::setw(10) << "in 95%"
	   << std::setw(12) << "ms/step" << "\n";
	auto num = [](double v, int prec) {  // NaN: not available
		std::ostringstream s;
		if (std::isnan(v)) s << "-";
		else s << std::fixed << std::setprecision(prec) << v;
		return s.str();
	};
	const double none = std::numeric_limits<double>::quiet_NaN();
	for (std::size_t i = 0; i < r.rows.size(); i++)
	{
		const RunRow& row = r.rows[i];
		const InertialFigures& f = r.figures[i];
		const double ape = row.has_ape ? row.ape_trans.rmse : none, mx = row.has_ape ? row.ape_trans.max : none;
		const double rot = f.rot_deg ? f.rot_deg->rmse : none, in = f.nees_inside ? 100 * *f.nees_inside : none;
		const double nees = f.nees_mean ? *f.nees_mean : none, rpe = row.has_rpe ? row.rpe_trans.rmse : none;
		os << std::left << std::setw(22) << row.label << std::right << std::setw(12) << num(ape, 4) << std::setw(12)
		   << num(mx, 4) << std::setw(12) << num(rpe, 4) << std::setw(14) << num(rot, 3) << std::setw(11) << num(nees, 2) << std::setw(10)
		   << num(in, 0) << std::setw(12) << num(row.ms_per_step, 3);
		if (row.interrupted) os << "  INTERRUPTED after " << row.failed_step << " steps";
		os << "\n";
	}
	return os.str();
}

nlohmann::json stats_json(const eval::Statistics& s)
{
	return {{"rmse", s.rmse}, {"mean", s.mean}, {"median", s.median}, {"max", s.max}, {"std", s.std}, {"count", s.count}};
}

void write_outputs(const RunOptions& o, const RunReport& rep, const Rows& r, const std::string& table,
				   std::vector<std::string>& files)
{
	nlohmann::json rows = nlohmann::json::array();
	for (std::size_t i = 0; i < r.rows.size(); i++)
	{
		const RunRow& row = r.rows[i];
		std::string name = row.label;
		for (char& c : name)
			if (c == ' ' || c == '=') c = '_';
		nlohmann::json file;  // null: an interrupted row has no estimate
		if (!row.interrupted)
		{
			const std::string tum = (fs::path(o.out_dir) / (name + ".tum")).string();
			eval::write_tum(tum, row.estimate);
			files.push_back(tum);
			file = name + ".tum";
		}
		nlohmann::json j = {{"name", row.name}, {"label", row.label}, {"trajectory", row.trajectory},
							{"file", file}, {"seconds", row.seconds}, {"steps", row.steps},
							{"ms_per_step", row.ms_per_step}};
		j["window"] = row.window > 0 ? nlohmann::json(row.window) : nlohmann::json();
		j["interrupted"] = row.interrupted;  // stopped by a signal before its estimator ran (doc/cli.md)
		if (row.has_ape)
		{
			j["ape_trans"] = stats_json(row.ape_trans);
			j["ape_rot_deg"] = stats_json(*r.figures[i].rot_deg);
		}
		if (row.has_rpe) j["rpe_trans"] = stats_json(row.rpe_trans);
		if (r.figures[i].nees_mean)
			j["position_nees"] = {{"mean", *r.figures[i].nees_mean}, {"fraction_in_95", *r.figures[i].nees_inside}};
		rows.push_back(j);
	}
	const nlohmann::json summary = {{"rawlog", rep.rawlog}, {"ground_truth", rep.ground_truth}, {"kind", "inertial"},
									{"keyframes", rep.steps}, {"rows", rows}};
	const std::string js = (fs::path(o.out_dir) / "summary.json").string(), ape = (fs::path(o.out_dir) / "ape.txt").string();
	// Through the atomic writer, as every output of swba run: a failed write is an error naming the file.
	write_text_file_atomically(js, summary.dump(2) + "\n");
	write_text_file_atomically(ape, table);
	files.push_back(ape);
	files.push_back(js);
}
/** The plots of swba run (top view, APE vs W, error over time, colormaps) of the rows other than dead
 * reckoning (whose metres-to-kilometres errors would set every scale) and the interrupted ones; notes go
 * to `log`. */
void write_inertial_plots(const RunOptions& o, const eval::Trajectory& gt, RunReport rep, std::vector<std::string>& files,
						  std::ostream& log)
{
	RunOptions po = o;
	po.policies.resize(1);
	po.fej.resize(1);
	std::vector<RunRow> shown;
	for (auto& r : rep.rows)
		if (r.name != "imu-only" && r.name != "odometry-only" && !r.interrupted) shown.push_back(std::move(r));
	rep.rows = std::move(shown);
	rep.files.clear();
	rep.notes.clear();  // the run's own notes are printed by run_inertial_app
	rep.time_label = "t (s)";
	if (eval::find_gnuplot().empty())
		rep.notes.push_back("gnuplot not found: plots not drawn; their data (.dat) and scripts (.gp) are in " + o.out_dir +
							"/ and " + o.out_dir + "/plots/");
	write_run_plots(po, gt, rep);
	files.insert(files.end(), rep.files.begin(), rep.files.end());
	for (const auto& n : rep.notes) log << "note: " << n << "\n";
}

/** The options given that an inertial rawlog has no use for (range-bearing and MRPT-EKF options that
 * differ from their defaults), by their command-line names. */
std::vector<std::string> inertial_ignored_options(const RunOptions& o)
{
	const RunOptions d;
	std::vector<std::string> out;
	if (o.max_steps != d.max_steps) out.push_back("--max-steps");
	if (o.ekf_methods != d.ekf_methods) out.push_back("--ekf-method");
	if (!o.ekf_ini.empty()) out.push_back("[ekf] ini_file");
	if (o.policies != d.policies) out.push_back("--policy");
	if (o.fej != d.fej) out.push_back("--fej");
	if (!o.association_truth.empty()) out.push_back("--association-truth");
	// The range-bearing window's options ([window], [sensor]): the inertial window has its own ([inertial]).
	const estimators::SlidingWindowOptions& w = o.window;
	const estimators::SlidingWindowOptions& dw = d.window;
	if (w.gauge != dw.gauge) out.push_back("--gauge (the inertial window's is [inertial] gauge)");
	if (w.landmarks != dw.landmarks) out.push_back("--landmarks");
	if (w.relinearized_poses != dw.relinearized_poses) out.push_back("--relinearized-poses");
	if (w.association != dw.association) out.push_back("--association");
	if (w.gate_readings != dw.gate_readings) out.push_back("--gate");
	if (w.gate_probability != dw.gate_probability) out.push_back("--gate-probability");
	if (w.robust_loss != dw.robust_loss) out.push_back("--robust-loss");
	if (w.robust_probability != dw.robust_probability) out.push_back("--robust-probability");
	if (w.sensor.std_range != dw.sensor.std_range) out.push_back("--sensor-std-range");
	if (w.sensor.std_yaw != dw.sensor.std_yaw) out.push_back("--sensor-std-yaw-deg");
	if (w.sensor.std_pitch != dw.sensor.std_pitch) out.push_back("--sensor-std-pitch-deg");
	if (o.verbose != d.verbose) out.push_back("--verbose");
	return out;
}

/** "t = <seconds> s" of a keyframe time, at the precision the reader gives (100 ns ticks). */
std::string keyframe_time(double t)
{
	std::ostringstream s;
	s << "t = " << std::setprecision(12) << t << " s";
	return s.str();
}

/** Throws std::runtime_error naming the rawlog and the first keyframe (of the window: a report time from
 * the initial state's time to the last IMU reading) with no IMU reading strictly between it and the
 * previous keyframe: its ImuPreintegrationFactor would integrate a single step (the two interpolated
 * ends), whose covariance is singular. Inputs without IMU readings or poses are left to the estimators,
 * which name them. */
void check_imu_readings_between_keyframes(const std::string& rawlog, const estimators::InertialInput& in,
										  estimators::KeyframeTimes keyframes)
{
	if (in.imu.size() < 2 || (in.pose_priors.empty() && in.odometry.empty())) return;
	const double t0 = in.pose_priors.empty() ? in.odometry.front().t : in.pose_priors.front().t;
	std::optional<double> previous;
	std::size_t i = 0;  // the first IMU reading after `previous`
	for (const double t : estimators::inertial_report_times(in, keyframes))
	{
		if (t < t0 || t > in.imu.back().t) continue;
		if (previous)
		{
			while (i < in.imu.size() && in.imu[i].t <= *previous) i++;
			std::size_t j = i;
			while (j < in.imu.size() && in.imu[j].t < t) j++;
			if (j == i)
				throw std::runtime_error(
						"rawlog '" + rawlog + "': the keyframe at " + keyframe_time(t) +
						" has 0 IMU readings between it and the previous keyframe (" + keyframe_time(*previous) +
						"): an IMU factor needs at least 1 (two integration steps), so the keyframes (" +
						(keyframes == estimators::KeyframeTimes::PoseReadings
								 ? "every pose reading: [inertial] keyframes = poses"
								 : "the pose priors, else the odometry poses") +
						") must come at most at half the IMU rate");
		}
		previous = t;
	}
}

/** Throws std::runtime_error naming the ground truth `path` and both time ranges when none of `gt`'s
 * stamps matches a report time of `in` (within kInertialGtMaxDiff, as the rows are scored). */
void check_ground_truth_matches(const std::string& path, const eval::Trajectory& gt, const estimators::InertialInput& in,
								estimators::KeyframeTimes keyframes)
{
	eval::Trajectory reports;
	for (const double t : estimators::inertial_report_times(in, keyframes)) reports.push_back(t, mrpt::poses::CPose3D());
	if (gt.empty() || reports.empty()) return;
	eval::AssociationOptions ao;
	ao.t_max_diff = kInertialGtMaxDiff;
	if (eval::associate(gt, reports, ao).size() > 0) return;
	std::ostringstream s;
	s << "ground truth '" << path << "': found no matching time stamps between the ground truth ("
	  << inertial_time_range(gt) << ") and the rawlog's keyframes (" << inertial_time_range(reports)
	  << ", seconds from its first observation) with max. time diff " << kInertialGtMaxDiff
	  << " s: the ground truth's stamps must be the rawlog's times, as swba simulate-imu writes them";
	throw std::runtime_error(s.str());
}
}  // namespace

std::string inertial_ground_truth_path(const RunOptions& o)
{
	if (!o.ground_truth.empty()) return o.ground_truth;
	fs::path p(o.rawlog);
	p.replace_extension();
	const std::string guess = p.string() + "_ground_truth.tum";
	return fs::exists(guess) ? guess : "";
}

RunReport run_inertial_app(const RunOptions& o, std::ostream& out, std::ostream& log,
							const std::function<bool()>& stop_requested)
{
	const io::ObservationRawlog raw = io::read_observation_rawlog(o.rawlog, o.sensors);
	const estimators::InertialInput in = estimators::inertial_input(raw);
	const estimators::KeyframeTimes keyframes = o.inertial.measurements.keyframes;
	check_imu_readings_between_keyframes(o.rawlog, in, keyframes);
	RunReport rep;
	rep.rawlog = o.rawlog;
	rep.ground_truth = inertial_ground_truth_path(o);
	rep.steps = estimators::inertial_report_times(in, keyframes).size();
	const eval::Trajectory gt = rep.ground_truth.empty() ? eval::Trajectory() : eval::read_tum(rep.ground_truth);
	check_ground_truth_matches(rep.ground_truth, gt, in, keyframes);
	log << "swba run: inertial rawlog " << o.rawlog << ": " << in.imu.size() << " IMU readings, " << in.pose_priors.size()
		<< " pose priors, " << in.odometry.size() << " odometry poses; ground truth: "
		<< (rep.ground_truth.empty() ? "none" : rep.ground_truth) << "\n";
	if (raw.ignored_entries > 0)
		log << "swba run: " << raw.ignored_entries << " of the " << raw.entries
			<< " rawlog entries skipped (other classes, or labels with no role in [sensors])\n";
	for (const auto& w : raw.warnings) log << "swba run: warning: " << w << "\n";
	const std::vector<std::string> ignored = inertial_ignored_options(o);
	for (std::size_t i = 0; i < ignored.size(); i++)
		log << (i == 0 ? "swba run: warning: not used on an inertial rawlog (doc/inertial.md), ignored: " : ", ")
			<< ignored[i] << (i + 1 == ignored.size() ? "\n" : "");
	prepare_output_directory(o.out_dir, "swba run", log);
	Rows r;
	run_rows(o, in, gt, stop_requested, r, log);
	const std::string table = format_table(r);
	rep.rows = r.rows;
	rep.notes = partial_match_notes(r, rep.ground_truth, gt);
	write_outputs(o, rep, r, table, rep.files);
	if (o.plots && !gt.empty()) write_inertial_plots(o, gt, rep, rep.files, log);
	write_run_manifest(o.out_dir, rep.files);
	out << table << std::flush;
	for (const auto& n : rep.notes) log << "note: " << n << "\n";
	detail::print_wrote_files(log, "swba run", rep.files.size(), o.out_dir);
	return rep;
}
}  // namespace swba::apps
