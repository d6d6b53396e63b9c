// swba run: MRPT's EKF, the sliding window (each W, online and lagged) and the batch solution on one
// rawlog, compared by APE against the ground truth (doc/run.md). Logic in swba/apps/run.h.
#include <swba/apps/run.h>

#include <cmath>
#include <csignal>
#include <cstdio>
#include <ctime>
#include <iostream>
#include <stdexcept>

#include "cli.h"
#include "command.h"

namespace swba::app
{
namespace
{
volatile std::sig_atomic_t g_signal = 0;
timespec g_first_signal = {};  // when g_signal was set; written only by the handler

/** The first SIGINT / SIGTERM asks the run to stop after the current step; one that comes at least 0.5 s
 * later kills it (the default action). A repeat within 0.5 s is the same request delivered twice: GNU
 * timeout and GNU parallel signal both the process and its process group. */
extern "C" void on_stop_signal(int sig)
{
	timespec now{};
	clock_gettime(CLOCK_MONOTONIC, &now);  // async-signal-safe, as are signal() and raise()
	if (g_signal == 0)
	{
		g_first_signal = now;
		g_signal = sig;
		return;
	}
	const double since = double(now.tv_sec - g_first_signal.tv_sec) + 1e-9 * double(now.tv_nsec - g_first_signal.tv_nsec);
	if (since < 0.5) return;
	std::signal(sig, SIG_DFL);
	std::raise(sig);  // delivered when the handler returns
}

/** What is complete is kept, the rest marked interrupted, and the exit code is 128 + the signal. */
void install_stop_handlers()
{
	struct sigaction sa = {};
	sa.sa_handler = on_stop_signal;
	sigemptyset(&sa.sa_mask);
	sa.sa_flags = 0;
	sigaction(SIGINT, &sa, nullptr);
	sigaction(SIGTERM, &sa, nullptr);
}

/** `--sensor-std-<what> X`: one noise of the bearing-range sensor, the same for every estimator. */
OverrideArg<double> sensor_noise_arg(const std::string& flag, const std::string& type_description,
									 const std::string& noise, TCLAP::CmdLineInterface& cmd)
{
	return {flag, type_description, "the observation's own", noise + " for every estimator", cmd};
}

/** The command line of `swba run`: every option, and how it overrides the INI's value. */
struct RunCommandLine
{
	TCLAP::CmdLine cmd{
		"Runs MRPT's EKF, the sliding-window estimator (each window size, online and lagged trajectories) and the "
		"batch solution on one rawlog and compares them by APE (not aligned) against the ground truth. Prints a "
		"table; writes TUM trajectories, ape.txt, ape.csv, summary.json, config.ini and plots into the output "
		"directory. Options: defaults < --config INI < command line.",
		' ', "0.1.0"};
	// In the order --help lists them (cli.cpp): input, main choices, tuning, output, verbosity.
	TCLAP::UnlabeledValueArg<std::string> rawlog{
		"RAWLOG", "MRPT rawlog with odometry and bearing-range observations (Default: kf-slam_6D_demo.rawlog of mrpt-common)",
		false, "", "RAWLOG", cmd};
	OverrideArg<std::string> gt{"gt", "FILE",
		"<rawlog name>_ground_truth_robot_path.txt next to the rawlog (inertial: <rawlog name>_ground_truth.tum), if "
		"present",
		"ground truth: MRPT's robot path (x y z yaw pitch roll per row) or a TUM trajectory, row i = pose at SF_i; "
		"inertial rawlog: a TUM trajectory, paired by time stamp",
		cmd};
	OverrideArg<std::string> association_truth{
		"association-truth", "RAWLOG", "the simulator's landmark file next to the rawlog, if present",
		"rawlog with the same readings and their landmark IDs: the truth the association of a rawlog without IDs is "
		"measured against", cmd};
	TCLAP::ValueArg<std::string> config{"", "config",
		"INI file with options (sections [run] [window] [solver] [ekf] [sensor] [odometry] [sensors] [inertial] "
		"[imu]; see " + share_dir() + "/config/swba_run.ini); unknown keys and keys given twice are errors",
		false, "", "INI", cmd};
	OverrideArg<std::string> windows{"windows", "LIST", "5,10,20,30", "window sizes W, comma-separated, each >= 2", cmd};
	OverrideArg<int> relinearized{"relinearized-poses", "K", "2",
		"poses of each window re-linearised at every step, the newest K (>= 2); the older ones are smoothed "
		"as frozen linear conditionals (doc/window.md); 0 = the whole window", cmd};
	TCLAP::SwitchArg no_ekf{"", "no-ekf", "do not run MRPT's EKF (on an inertial rawlog: the ESKF)", cmd};
	TCLAP::SwitchArg no_batch{"", "no-batch", "do not run the batch estimator", cmd};
	TCLAP::SwitchArg causal{
		"", "causal",
		"also run the full-history causal optimum (online W=inf: re-solve the whole history after every step; O(steps^2))",
		cmd};
	OverrideArg<std::string> ekf_method{"ekf-method", "NAME,...", "kfEKFAlaDavison,kfEKFNaive",
		"MRPT EKF methods, comma-separated: kfEKFNaive, kfEKFAlaDavison, kfIKFFull", cmd};
	OverrideArg<std::string> policy{"policy", "P", "slam",
		"landmark policy of the window: slam, constant-time, map, a comma-separated list, both or all", cmd};
	OverrideArg<std::string> fej{"fej", "on|off|both", "on", "first-estimate Jacobians: on, off or both", cmd};
	OverrideArg<std::string> landmarks{"landmarks", "P", "inverse-depth",
		"landmark parameterisation: inverse-depth or xyz", cmd};
	OverrideArg<std::string> gauge{"gauge", "G", "fixed", "gauge: fixed (first pose constant), free or prior", cmd};
	OverrideArg<std::string> association{"association", "A", "auto",
		"data association of the readings (doc/association.md): auto (the readings' landmark IDs if every "
		"reading has one, else jcbb), ids, nn or jcbb", cmd};
	OverrideArg<double> std_range = sensor_noise_arg("sensor-std-range", "M", "range noise (m)", cmd);
	OverrideArg<double> std_yaw = sensor_noise_arg("sensor-std-yaw-deg", "D", "yaw noise (deg)", cmd);
	OverrideArg<double> std_pitch = sensor_noise_arg("sensor-std-pitch-deg", "D", "pitch noise (deg)", cmd);
	OverrideArg<std::string> gate{"gate", "on|off", "off",
		"chi-square gate of the bearing-range readings (doc/outliers.md): on or off", cmd};
	OverrideArg<double> gate_probability{"gate-probability", "P", "0.999",
		"share of correct readings the gate passes, in (0, 1)", cmd};
	OverrideArg<std::string> robust_loss{"robust-loss", "L", "cauchy",
		"robust loss of the range-bearing factors, window and batch: none, huber or cauchy", cmd};
	OverrideArg<double> robust_probability{"robust-probability", "P", "0.99",
		"robust-loss scale = sqrt of the chi-square (3 DoF) quantile at this probability, in (0, 1)", cmd};
	OverrideArg<int> max_steps{"max-steps", "N", "0", "process at most N steps (0 = all)", cmd};
	OverrideArg<int> threads{"threads", "N", "1", "solver threads", cmd};
	OverrideArg<std::string> out{"out", "DIR", "swba_out", "output directory, created", cmd};
	TCLAP::SwitchArg no_plots{"", "no-plots", "do not write gnuplot plots", cmd};
	TCLAP::SwitchArg no_progress{"", "no-progress", "no progress lines on stderr", cmd};
	TCLAP::SwitchArg verbose{
		"", "verbose", "each solve's summary on stderr: a line per window step, the batch's full report", cmd};

	/** Overrides `o` with the options given on the command line (only those; TCLAP reads are not const). */
	void apply(apps::RunOptions& o)
	{
		if (rawlog.isSet()) o.rawlog = rawlog.getValue();
		if (gt.isSet()) o.ground_truth = gt.getValue();
		if (association_truth.isSet()) o.association_truth = association_truth.getValue();
		if (windows.isSet()) o.windows = apps::parse_window_list(windows.getValue(), "--windows");
		if (relinearized.isSet())
		{
			if (relinearized.getValue() < 0 || relinearized.getValue() == 1)
				throw UsageError("--relinearized-poses must be >= 2 or 0");
			o.window.relinearized_poses = relinearized.getValue();
		}
		if (no_ekf.isSet()) o.run_ekf = false;
		if (no_batch.isSet()) o.run_batch = false;
		if (causal.isSet()) o.run_causal = true;
		if (out.isSet()) o.out_dir = out.getValue();
		if (ekf_method.isSet()) o.ekf_methods = apps::parse_ekf_method_list(ekf_method.getValue());
		if (policy.isSet()) o.policies = apps::parse_policy_list(policy.getValue());
		if (fej.isSet()) o.fej = apps::parse_fej_list(fej.getValue());
		if (landmarks.isSet()) o.window.landmarks = estimators::parse_landmark_parameterization(landmarks.getValue());
		if (gauge.isSet()) o.window.gauge = parse_gauge_mode(gauge.getValue());
		if (association.isSet())
			o.window.association = parse_enum<estimators::DataAssociation>(association.getValue(), "data association");
		apply_noise(o);
		apply_outliers(o.window);
		if (max_steps.isSet())
		{
			if (max_steps.getValue() < 0) throw UsageError("--max-steps must be >= 0");
			o.max_steps = static_cast<std::size_t>(max_steps.getValue());
		}
		if (threads.isSet())
		{
			if (threads.getValue() < 1) throw UsageError("--threads must be >= 1");
			o.window.solver.num_threads = threads.getValue();
		}
		if (no_plots.isSet()) o.plots = false;
		if (no_progress.isSet()) o.progress = false;
		if (verbose.isSet()) o.verbose = true;
	}

	/** The gate and the robust loss; a probability outside (0, 1) is a usage error naming its flag. */
	void apply_outliers(estimators::SlidingWindowOptions& w)
	{
		if (gate.isSet())
		{
			if (gate.getValue() != "on" && gate.getValue() != "off") throw UsageError("--gate must be on or off");
			w.gate_readings = gate.getValue() == "on";
		}
		auto probability = [](TCLAP::ValueArg<double>& a, double& dst) {
			if (!a.isSet()) return;
			if (!(a.getValue() > 0 && a.getValue() < 1))
			{
				char got[32];
				std::snprintf(got, sizeof got, "%g", a.getValue());
				throw UsageError("--" + a.getName() + " must be in (0, 1), got " + got);
			}
			dst = a.getValue();
		};
		probability(gate_probability, w.gate_probability);
		if (robust_loss.isSet()) w.robust_loss = parse_enum<RobustLoss>(robust_loss.getValue(), "robust loss");
		probability(robust_probability, w.robust_probability);
	}

	/** Sensor noise: degrees on the command line, radians inside. */
	void apply_noise(apps::RunOptions& o)
	{
		constexpr double kDegToRad = 3.14159265358979323846 / 180.0;
		auto noise = [](TCLAP::ValueArg<double>& a, double scale, double& dst) {
			if (!a.isSet()) return;
			if (!std::isfinite(a.getValue()) || a.getValue() <= 0)
				throw UsageError("--" + a.getName() + " must be a number > 0");
			dst = a.getValue() * scale;
		};
		noise(std_range, 1.0, o.window.sensor.std_range);
		noise(std_yaw, kDegToRad, o.window.sensor.std_yaw);
		noise(std_pitch, kDegToRad, o.window.sensor.std_pitch);
	}
};

int run_run(int argc, char** argv)
{
	install_stop_handlers();  // first: a signal during the rawlog's reading is honoured too
	RunCommandLine cl;
	if (auto rc = parse_command_line(cl.cmd, argc, argv, "one rawlog per run; for several, see swba jobs"))
		return *rc;
	apps::RunOptions from_file;
	if (cl.config.isSet()) apps::load_run_config(cl.config.getValue(), from_file);  // a bad file: exit 1
	apps::RunOptions o = from_file;
	try
	{
		cl.apply(o);
		o.validate();  // options that exclude each other (e.g. --policy map with --gauge free)
	}
	catch (const std::invalid_argument& e)
	{
		// Options that exclude each other within the file alone are the file's error (exit 1), named.
		try
		{
			if (cl.config.isSet()) from_file.validate();
		}
		catch (const std::invalid_argument& in_file)
		{
			throw std::runtime_error("config '" + cl.config.getValue() + "': " + in_file.what());
		}
		throw UsageError(e.what());
	}
	if (o.rawlog.empty()) o.rawlog = std::string(SWBA_DEFAULT_DATASETS) + "/kf-slam_6D_demo.rawlog";
	const apps::RunReport report = apps::run_app(o, std::cout, std::cerr, [] { return g_signal != 0; });
	if (g_signal)
	{
		std::cerr << "swba run: interrupted by " << (g_signal == SIGINT ? "SIGINT" : "SIGTERM")
				  << ": the complete rows are in " << o.out_dir << "/, the others marked interrupted in summary.json\n";
		return 128 + g_signal;
	}
	if (apps::every_estimator_failed(report))
	{
		std::cerr << "swba run: error: every estimator failed (see the table)\n";
		return 1;
	}
	if (apps::some_estimator_failed_or_diverged(report))
	{
		std::cerr << "swba run: error: an estimator failed or diverged (see the table and the notes)\n";
		return 3;
	}
	return 0;
}
SWBA_REGISTER_COMMAND("run", "EKF vs sliding window vs batch on an MRPT rawlog: APE table and files", run_run);
}  // namespace
}  // namespace swba::app
