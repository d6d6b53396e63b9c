// swba run: MRPT's EKF, the sliding window (each W, online and lagged) and the batch solution on one
// rawlog, compared by APE against the ground truth (doc/run.md). Logic in swba/estimators/run_app.h.
#include <swba/estimators/run_app.h>

#include <cmath>
#include <iostream>

#include "cli.h"
#include "command.h"

namespace swba::app
{
namespace
{
int run_run(int argc, char** argv)
{
	using estimators::RunOptions;
	TCLAP::CmdLine cmd(
		"Runs MRPT's EKF, the sliding-window estimator (each window size, online and lagged trajectories) and the "
		"batch solution on one rawlog and compares them by APE (not aligned) against the ground truth. Prints a "
		"table; writes TUM trajectories, ape.txt, ape.csv, summary.json, config.ini and plots into the output "
		"directory. Options: defaults < --config INI < command line.",
		' ', "0.1.0");
	TCLAP::UnlabeledValueArg<std::string> rawlog_arg(
		"RAWLOG", "MRPT rawlog with odometry and bearing-range observations. (Default: kf-slam_6D_demo.rawlog of mrpt-common)",
		false, "", "RAWLOG");
	TCLAP::ValueArg<std::string> gt_arg(
		"", "gt",
		"MRPT ground-truth robot path (x y z yaw pitch roll per row, row i = pose at SF_i). (Default: "
		"<rawlog name>_ground_truth_robot_path.txt next to the rawlog, if present)",
		false, "", "FILE");
	TCLAP::ValueArg<std::string> windows_arg("", "windows", "window sizes W, comma-separated, each >= 2. (Default: 5,10,20,30)",
											 false, "", "LIST");
	TCLAP::SwitchArg no_ekf_arg("", "no-ekf", "do not run MRPT's EKF");
	TCLAP::SwitchArg no_batch_arg("", "no-batch", "do not run the batch estimator");
	TCLAP::SwitchArg causal_arg("", "causal",
								"also run the full-history causal optimum (online W=inf: re-solve the whole history after "
								"every step; O(steps^2))");
	TCLAP::ValueArg<std::string> out_arg("", "out", "output directory, created. (Default: swba_out)", false, "", "DIR");
	TCLAP::ValueArg<std::string> config_arg(
		"", "config", "INI file with options (sections [run] [window] [solver] [ekf] [sensor] [odometry]; see "
					  "share/config/swba_run.ini); unknown keys are errors",
		false, "", "INI");
	TCLAP::ValueArg<std::string> ekf_method_arg(
		"", "ekf-method", "MRPT EKF methods, comma-separated: kfEKFNaive, kfEKFAlaDavison, kfIKFFull, kfIKF. (Default: "
						  "kfEKFAlaDavison,kfEKFNaive)",
		false, "", "NAME,...");
	TCLAP::ValueArg<std::string> policy_arg(
		"", "policy", "landmark policy of the window: slam, constant-time or both. (Default: slam)", false, "", "P");
	TCLAP::ValueArg<std::string> fej_arg("", "fej", "first-estimate Jacobians: on, off or both. (Default: on)", false, "",
										 "on|off|both");
	TCLAP::ValueArg<std::string> landmarks_arg("", "landmarks", "landmark parameterisation: inverse-depth or xyz. (Default: "
																"inverse-depth)",
											   false, "", "P");
	TCLAP::ValueArg<std::string> gauge_arg("", "gauge", "gauge: fixed (first pose constant), free or prior. (Default: fixed)",
										   false, "", "G");
	TCLAP::ValueArg<double> std_range_arg("", "sensor-std-range",
										  "range noise (m) for every estimator. (Default: the observation's own)", false, 0,
										  "M");
	TCLAP::ValueArg<double> std_yaw_arg("", "sensor-std-yaw-deg",
										"yaw noise (deg) for every estimator. (Default: the observation's own)", false, 0, "D");
	TCLAP::ValueArg<double> std_pitch_arg("", "sensor-std-pitch-deg",
										  "pitch noise (deg) for every estimator. (Default: the observation's own)", false,
										  0, "D");
	TCLAP::ValueArg<int> max_steps_arg("", "max-steps", "process at most N steps (0 = all). (Default: 0)", false, 0, "N");
	TCLAP::ValueArg<int> threads_arg("", "threads", "solver threads. (Default: 1)", false, 1, "N");
	TCLAP::SwitchArg no_plots_arg("", "no-plots", "do not write gnuplot plots");
	TCLAP::SwitchArg quiet_arg("", "no-progress", "no progress lines on stderr");
	cmd.add(rawlog_arg);
	for (TCLAP::Arg* a : std::initializer_list<TCLAP::Arg*>{
			 &quiet_arg, &no_plots_arg, &threads_arg, &max_steps_arg, &std_pitch_arg, &std_yaw_arg, &std_range_arg,
			 &gauge_arg, &landmarks_arg, &fej_arg, &policy_arg, &ekf_method_arg, &config_arg, &out_arg, &causal_arg,
			 &no_batch_arg, &no_ekf_arg, &windows_arg, &gt_arg})
		cmd.add(*a);
	if (auto rc = parse_command_line(cmd, argc, argv)) return *rc;

	RunOptions o;
	if (config_arg.isSet()) estimators::load_run_config(config_arg.getValue(), o);
	// Command-line options override the INI (only those given).
	try
	{
		if (rawlog_arg.isSet()) o.rawlog = rawlog_arg.getValue();
		if (gt_arg.isSet()) o.ground_truth = gt_arg.getValue();
		if (windows_arg.isSet()) o.windows = estimators::parse_window_list(windows_arg.getValue(), "--windows");
		if (no_ekf_arg.isSet()) o.run_ekf = false;
		if (no_batch_arg.isSet()) o.run_batch = false;
		if (causal_arg.isSet()) o.run_causal = true;
		if (out_arg.isSet()) o.out_dir = out_arg.getValue();
		if (ekf_method_arg.isSet()) o.ekf_methods = estimators::parse_ekf_method_list(ekf_method_arg.getValue());
		if (policy_arg.isSet()) o.policies = estimators::parse_policy_list(policy_arg.getValue());
		if (fej_arg.isSet()) o.fej = estimators::parse_fej_list(fej_arg.getValue());
		if (landmarks_arg.isSet()) o.window.landmarks = estimators::parse_landmark_parameterization(landmarks_arg.getValue());
		if (gauge_arg.isSet()) o.window.gauge = parse_gauge_mode(gauge_arg.getValue());
		constexpr double kDegToRad = 3.14159265358979323846 / 180.0;
		auto noise = [](TCLAP::ValueArg<double>& a, double scale, double& dst) {
			if (!a.isSet()) return;
			if (!std::isfinite(a.getValue()) || a.getValue() <= 0)
				throw UsageError("--" + a.getName() + " must be a number > 0");
			dst = a.getValue() * scale;
		};
		noise(std_range_arg, 1.0, o.window.sensor_std_range);
		noise(std_yaw_arg, kDegToRad, o.window.sensor_std_yaw);
		noise(std_pitch_arg, kDegToRad, o.window.sensor_std_pitch);
		if (max_steps_arg.isSet())
		{
			if (max_steps_arg.getValue() < 0) throw UsageError("--max-steps must be >= 0");
			o.max_steps = static_cast<std::size_t>(max_steps_arg.getValue());
		}
		if (threads_arg.isSet())
		{
			if (threads_arg.getValue() < 1) throw UsageError("--threads must be >= 1");
			o.threads = threads_arg.getValue();
		}
		if (no_plots_arg.isSet()) o.plots = false;
		if (quiet_arg.isSet()) o.progress = false;
	}
	catch (const std::invalid_argument& e)
	{
		throw UsageError(e.what());
	}
	if (o.rawlog.empty()) o.rawlog = std::string(SWBA_DEFAULT_DATASETS) + "/kf-slam_6D_demo.rawlog";
	estimators::run_app(o, std::cout, std::cerr);
	return 0;
}
SWBA_REGISTER_COMMAND("run", "EKF vs sliding window vs batch on an MRPT rawlog: APE table and files", run_run);
}  // namespace
}  // namespace swba::app
