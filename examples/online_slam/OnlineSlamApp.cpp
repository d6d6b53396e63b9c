#include "OnlineSlamApp.h"

#include <swba/apps/run_options.h>
#include <swba/eval/trajectory.h>

#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/filesystem.h>

#include <cstdio>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <vector>

namespace
{
/** TCLAP output that turns a parse error into an exception instead of printing the usage. */
class ThrowingOutput : public TCLAP::StdOutput
{
   public:
	void failure(TCLAP::CmdLineInterface&, TCLAP::ArgException& e) override
	{
		throw std::invalid_argument(e.argId() + ": " + e.error() + " (see --help)");
	}
};

/** One TUM row "t x y z qx qy qz qw" (swba::eval::write_tum's format, as in swba run's files). */
void print_pose(const char* what, double t, const mrpt::poses::CPose3D& p)
{
	swba::eval::Trajectory one;
	one.push_back(t, p);
	std::cout << what << ": ";
	swba::eval::write_tum(std::cout, one);
	std::cout.flush();
}

/** The poses estimated after a step (t >= 1): the initial pose (t = 0) is not an estimate. */
swba::eval::Trajectory after_steps(const swba::eval::Trajectory& t)
{
	swba::eval::Trajectory out;
	for (std::size_t i = 0; i < t.size(); i++)
		if (t.stamps[i] >= 0.5) out.push_back(t.stamps[i], t.poses[i]);
	return out;
}
}  // namespace

bool OnlineSlamApp::initialize(int argc, char** argv)
{
	// MRPT's TCLAP, as MRPT's own apps parse their command lines.
	TCLAP::CmdLine cmd(
		"Runs swba's sliding-window estimator on an MRPT rawlog (odometry + CObservationBearingRange), feeding it one "
		"CActionCollection/CSensoryFrame pair at a time, as an online application would.",
		' ', "0.1.0");
	TCLAP::UnlabeledValueArg<std::string> rawlog_arg("RAWLOG", "MRPT rawlog", true, "", "RAWLOG", cmd);
	TCLAP::ValueArg<int> window_arg("", "window", "poses in the window, >= 2. (Default: 10, or the first of [run] windows in --config)",
									false, 10, "W", cmd);
	TCLAP::ValueArg<std::string> config_arg("", "config", "swba run's INI file ([window] [solver] [sensor] [odometry] [run] sections)",
											false, "", "INI", cmd);
	TCLAP::ValueArg<int> threads_arg("", "threads", "solver threads. (Default: 1, or [solver] threads in --config)", false, 1, "N", cmd);
	TCLAP::ValueArg<int> max_steps_arg("", "max-steps", "stop after N steps (0 = all). (Default: 0)", false, 0, "N", cmd);
	TCLAP::ValueArg<std::string> tum_arg("", "tum", "write the online trajectory (each pose right after its step), TUM", false, "",
										 "FILE", cmd);
	TCLAP::ValueArg<std::string> lagged_arg("", "lagged-tum", "write the lagged trajectory (each pose when it left the window), TUM",
											false, "", "FILE", cmd);
	TCLAP::ValueArg<int> print_every_arg("", "print-every", "a progress line every N steps (0 = none). (Default: 100)", false, 100,
										 "N", cmd);
	ThrowingOutput out;  // a parse error becomes std::invalid_argument (main prints it, exits 1)
	// TCLAP's setOutput() forgets, without deleting it, the output object the CmdLine allocated: own it.
	const std::unique_ptr<TCLAP::CmdLineOutput> tclap_default_output(cmd.getOutput());
	cmd.setOutput(&out);
	const bool go_on = cmd.parse(argc, argv);
	cmd.setOutput(nullptr);
	if (!go_on) return false;  // --help or --version was printed

	rawlog_path = rawlog_arg.getValue();
	if (rawlog_path.rfind('-', 0) == 0) throw std::invalid_argument("unknown option " + rawlog_path + " (see --help)");
	online_tum = tum_arg.getValue();
	lagged_tum = lagged_arg.getValue();
	if (max_steps_arg.getValue() < 0 || print_every_arg.getValue() < 0)
		throw std::invalid_argument("--max-steps and --print-every must be >= 0");
	max_steps = static_cast<std::size_t>(max_steps_arg.getValue());
	print_every = static_cast<std::size_t>(print_every_arg.getValue());

	swba::apps::RunOptions run;  // swba run's options: the same defaults and INI keys
	if (config_arg.isSet()) swba::apps::load_run_config(config_arg.getValue(), run);
	options = run.window;
	options.window_size = config_arg.isSet() && !run.windows.empty() ? run.windows.front() : 10;
	if (window_arg.isSet()) options.window_size = window_arg.getValue();
	if (threads_arg.isSet())
	{
		if (threads_arg.getValue() < 1) throw std::invalid_argument("--threads must be >= 1");
		options.solver.num_threads = threads_arg.getValue();
	}
	options.validate();  // window_size >= 2, ...
	return true;
}

void OnlineSlamApp::run()
{
	if (!mrpt::system::fileExists(rawlog_path)) throw std::runtime_error("rawlog '" + rawlog_path + "': no such file");
	mrpt::io::CFileGZInputStream file;
	std::string error;
	if (!file.open(rawlog_path, error)) throw std::runtime_error("rawlog '" + rawlog_path + "': cannot open: " + error);
	auto archive = mrpt::serialization::archiveFrom(file);

	swba::estimators::MrptSlidingWindow slam(options);
	mrpt::obs::CActionCollection::Ptr actions;
	mrpt::obs::CSensoryFrame::Ptr frame;
	std::size_t entry = 0;
	double iterations = 0, seconds = 0;
	// The online loop: one (odometry, observations) pair at a time.
	while ((!max_steps || slam.converter().steps() < max_steps) &&
		   mrpt::obs::CRawlog::readActionObservationPair(archive, actions, frame, entry))
	{
		const swba::estimators::StepSummary& s = slam.process(actions, frame);
		iterations += s.iterations;
		seconds += s.seconds;
		if (print_every && (s.step + 1) % print_every == 0)
		{
			const mrpt::poses::CPose3D p = slam.current_pose();
			std::printf("step %4zu: x=%8.3f y=%8.3f z=%7.3f | window %d poses, %d landmarks, prior rank %d, %d LM it.\n",
						s.step, p.x(), p.y(), p.z(), s.window_poses, s.landmarks, s.prior_rank, s.iterations);
		}
	}
	const std::size_t steps = slam.converter().steps();
	if (steps == 0) throw std::runtime_error("rawlog '" + rawlog_path + "': no action/sensory-frame pair");
	slam.finish();

	const auto window = slam.window_poses();
	std::printf("steps: %zu, window: W=%d, landmarks: %zu, mean LM iterations: %.2f, mean %.2f ms/step\n", steps,
				options.window_size, slam.landmarks().size(), iterations / static_cast<double>(steps),
				seconds * 1e3 / static_cast<double>(steps));
	if (!window.empty()) print_pose("oldest window pose", window.front().first, window.front().second);
	print_pose("final pose", static_cast<double>(steps), slam.current_pose());

	const swba::eval::Trajectory& online = slam.estimator().online_trajectory();
	if (!online_tum.empty()) swba::eval::write_tum(online_tum, after_steps(online));
	if (!lagged_tum.empty()) swba::eval::write_tum(lagged_tum, after_steps(slam.estimator().lagged_trajectory()));
}
