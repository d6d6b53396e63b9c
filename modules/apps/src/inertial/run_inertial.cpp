#include <swba/apps/inertial_run.h>

#include "../run/output_dir.h"
#include "../run/plots.h"

#include <swba/core/chi2.h>
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
#include <ostream>
#include <sstream>

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
};

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
	ao.t_max_diff = 1e-6;
	const eval::Association a = eval::associate(gt, row.estimate, ao);
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

double seconds_of(const std::function<void()>& f)
{
	const auto t0 = SteadyClock::now();
	f();
	return seconds_since(t0);
}

void run_rows(const RunOptions& o, const estimators::InertialInput& in, const eval::Trajectory& gt, Rows& r,
			  std::ostream& log)
{
	estimators::InertialWindowOptions wo = o.inertial;
	wo.solver.num_threads = o.window.solver.num_threads;
	const std::vector<double> reports = estimators::inertial_report_times(in, wo.measurements.keyframes);
	const std::size_t kf = reports.size();
	estimators::InertialTrajectory t;
	double s = 0;
	if (o.run_ekf)  // --no-ekf: the filter row is the ESKF's here
	{
		s = seconds_of([&] { t = estimators::run_inertial_filter(in, wo.measurements); });
		add_row(r, "eskf", "eskf", 0, "online", t, s, t.imu_steps, gt);
	}
	estimators::InertialFilterOptions dr = wo.measurements;
	dr.use_pose_priors = dr.use_odometry = false;
	s = seconds_of([&] { t = estimators::run_inertial_filter(in, dr); });
	add_row(r, "imu-only", "imu only", 0, "online", t, s, t.imu_steps, gt);
	if (!in.odometry.empty())
	{
		s = seconds_of([&] { t = estimators::run_odometry_dead_reckoning(in, dr.prior, reports); });
		add_row(r, "odometry-only", "odometry only", 0, "online", t, s, t.t.size(), gt);
	}
	for (int W : o.windows)
	{
		wo.window_size = W;
		estimators::InertialWindowResult w;
		s = seconds_of([&] { w = estimators::run_inertial_window(in, wo); });
		const std::string label = "window W=" + std::to_string(W);
		add_row(r, "window", label, W, "online", w.online, s, kf, gt);
		add_row(r, "window", label + " lagged", W, "lagged", w.lagged, s, kf, gt);
		if (o.progress) log << "swba run: " << label << " done (" << w.reintegrations << " re-integrations)\n";
	}
	if (o.run_batch)
	{
		s = seconds_of([&] { t = estimators::run_inertial_batch(in, wo); });
		add_row(r, "batch", "batch", 0, "smoothed", t, s, kf, gt);
	}
	if (o.run_causal)
	{
		wo.window_size = 0;
		estimators::InertialWindowResult w;
		s = seconds_of([&] { w = estimators::run_inertial_window(in, wo); });
		add_row(r, "causal", "causal", 0, "online", w.online, s, kf, gt);
	}
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
		   << num(in, 0) << std::setw(12) << num(row.ms_per_step, 3) << "\n";
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
		const std::string tum = (fs::path(o.out_dir) / (name + ".tum")).string();
		eval::write_tum(tum, row.estimate);
		files.push_back(tum);
		nlohmann::json j = {{"name", row.name}, {"label", row.label}, {"trajectory", row.trajectory},
							{"file", name + ".tum"}, {"seconds", row.seconds}, {"steps", row.steps},
							{"ms_per_step", row.ms_per_step}};
		j["window"] = row.window > 0 ? nlohmann::json(row.window) : nlohmann::json();
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
	std::ofstream(js) << summary.dump(2) << "\n";
	std::ofstream(ape) << table;
	files.push_back(ape);
	files.push_back(js);
}
/** The plots of swba run (top view, APE vs W, error over time, colormaps) of the rows other than dead
 * reckoning (whose metres-to-kilometres errors would set every scale); notes go to `log`. */
void write_inertial_plots(const RunOptions& o, const eval::Trajectory& gt, RunReport rep, std::vector<std::string>& files,
						  std::ostream& log)
{
	RunOptions po = o;
	po.policies.resize(1);
	po.fej.resize(1);
	std::vector<RunRow> shown;
	for (auto& r : rep.rows)
		if (r.name != "imu-only" && r.name != "odometry-only") shown.push_back(std::move(r));
	rep.rows = std::move(shown);
	rep.files.clear();
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
	return out;
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

RunReport run_inertial_app(const RunOptions& o, std::ostream& out, std::ostream& log)
{
	const io::ObservationRawlog raw = io::read_observation_rawlog(o.rawlog, o.sensors);
	const estimators::InertialInput in = estimators::inertial_input(raw);
	RunReport rep;
	rep.rawlog = o.rawlog;
	rep.ground_truth = inertial_ground_truth_path(o);
	rep.steps = estimators::inertial_report_times(in, o.inertial.measurements.keyframes).size();
	const eval::Trajectory gt = rep.ground_truth.empty() ? eval::Trajectory() : eval::read_tum(rep.ground_truth);
	log << "swba run: inertial rawlog " << o.rawlog << ": " << in.imu.size() << " IMU readings, " << in.pose_priors.size()
		<< " pose priors, " << in.odometry.size() << " odometry poses; ground truth: "
		<< (rep.ground_truth.empty() ? "none" : rep.ground_truth) << "\n";
	const std::vector<std::string> ignored = inertial_ignored_options(o);
	for (std::size_t i = 0; i < ignored.size(); i++)
		log << (i == 0 ? "swba run: warning: not used on an inertial rawlog (doc/inertial.md), ignored: " : ", ")
			<< ignored[i] << (i + 1 == ignored.size() ? "\n" : "");
	prepare_output_directory(o.out_dir, "swba run", log);
	Rows r;
	run_rows(o, in, gt, r, log);
	const std::string table = format_table(r);
	rep.rows = r.rows;
	write_outputs(o, rep, r, table, rep.files);
	if (o.plots && !gt.empty()) write_inertial_plots(o, gt, rep, rep.files, log);
	write_run_manifest(o.out_dir, rep.files);
	out << table << std::flush;
	log << "swba run: wrote " << rep.files.size() << " files into " << o.out_dir << "/\n";
	return rep;
}
}  // namespace swba::apps
