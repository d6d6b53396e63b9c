#include "OnlineSlamApp.h"

#include <swba/core/file.h>
#include <swba/core/ini.h>
#include <swba/eval/trajectory.h>
#include <swba/io/rawlog.h>

#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>
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

/** The window's options from swba run's INI (share/config/swba_run.ini documents every key): the keys
 * of [window], [solver], [sensor] and [odometry] that the file sets, read through the key tables each
 * options struct declares (swba/core/ini.h). swba run's own keys ([run], the sweep's sizes, policy and
 * fej, [ekf]) are not the window's and are left to it; the first of [window] sizes is the window. */
void load_window_options(const std::string& path, swba::estimators::SlidingWindowOptions& o)
{
	using swba::estimators::SlidingWindowOptions;
	const mrpt::config::CConfigFileMemory ini(swba::read_text_file(path, "config"));  // names a missing or binary file
	swba::IniKeys<SlidingWindowOptions> keys = SlidingWindowOptions::ini_keys("window");
	swba::append_keys(keys, swba::SolverOptions::ini_keys("solver"), [](auto& w) -> auto& { return w.solver; });
	swba::append_keys(keys, swba::estimators::SensorNoiseOptions::ini_keys("sensor"),
					  [](auto& w) -> auto& { return w.sensor; });
	swba::append_keys(keys, swba::io::OdometryInformationOptions::ini_keys("odometry"),
					  [](auto& w) -> auto& { return w.odometry; });
	for (const auto& k : keys)
	{
		const std::string value = ini.read_string(k.section, k.key, "");
		if (value.empty()) continue;
		try
		{
			k.set(value, o);
		}
		catch (const std::invalid_argument& e)
		{
			throw std::runtime_error("config '" + path + "': [" + k.section + "] " + k.key + ": " + e.what());
		}
	}
	const std::string sizes = ini.read_string("window", "sizes", "");
	if (!sizes.empty()) o.window_size = static_cast<int>(swba::ini::parse_integer(sizes.substr(0, sizes.find(','))));
}

/** The largest standard deviation of a landmark's position (m): the square root of the largest
 * eigenvalue of its marginal covariance. */
double largest_std(const Eigen::Matrix3d& covariance)
{
	return std::sqrt(std::max(0.0, Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(covariance).eigenvalues().maxCoeff()));
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
	TCLAP::ValueArg<int> window_arg("", "window", "poses in the window, >= 2. (Default: 10, or the first of [window] sizes in --config)",
									false, 10, "W", cmd);
	TCLAP::ValueArg<std::string> config_arg("", "config", "swba run's INI file: its [window] [solver] [sensor] [odometry] keys are read, the others ignored",
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

	options = swba::estimators::SlidingWindowOptions{};  // swba run's defaults
	options.window_size = 10;
	if (config_arg.isSet()) load_window_options(config_arg.getValue(), options);
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
	// A robot hands the pairs over as they arrive; here they come from the file, read and checked by
	// swba::io::read_rawlog (a truncated or corrupt rawlog is an error naming the entry, where MRPT's
	// CRawlog::readActionObservationPair would just stop early). The readings need no landmark ID: the
	// window associates those without one (SlidingWindowOptions::association, Auto by default).
	swba::io::RawlogReaderOptions reader;
	reader.max_steps = max_steps;
	reader.require_landmark_ids = false;
	const swba::io::Rawlog rawlog = swba::io::read_rawlog(rawlog_path, reader);

	swba::estimators::MrptSlidingWindow slam(options, swba::estimators::MrptStepConverterOptions{false});
	double iterations = 0, seconds = 0;
	// The online loop: one (odometry, observations) pair at a time.
	for (const swba::io::RawlogStep& step : rawlog.steps)
	{
		const swba::estimators::StepSummary& s = slam.process(step.actions, step.observations);
		iterations += s.iterations;
		seconds += s.seconds;
		if (print_every && (s.step + 1) % print_every == 0) print_step(slam, s);
	}
	const std::size_t steps = slam.converter().steps();
	slam.finish();

	const auto window = slam.window_poses();
	std::printf("steps: %zu, window: W=%d, landmarks: %zu, mean LM iterations: %.2f, mean %.2f ms/step\n", steps,
				options.window_size, slam.landmarks().size(), iterations / static_cast<double>(steps),
				seconds * 1e3 / static_cast<double>(steps));
	if (!window.empty()) print_pose("oldest window pose", window.front().first, window.front().second);
	print_pose("final pose", static_cast<double>(steps), slam.current_pose());
	print_landmarks(slam);

	const swba::eval::Trajectory& online = slam.estimator().online_trajectory();
	if (!online_tum.empty()) swba::eval::write_tum(online_tum, after_steps(online));
	if (!lagged_tum.empty()) swba::eval::write_tum(lagged_tum, after_steps(slam.estimator().lagged_trajectory()));
}

void OnlineSlamApp::print_step(const swba::estimators::MrptSlidingWindow& slam, const swba::estimators::StepSummary& s)
{
	const mrpt::poses::CPose3D p = slam.current_pose();
	std::printf("step %4zu: x=%8.3f y=%8.3f z=%7.3f | window %d poses, %d landmarks, prior rank %d, %d LM it.\n", s.step,
				p.x(), p.y(), p.z(), s.window_poses, s.landmarks, s.prior_rank, s.iterations);
	// The association of this step's readings: reading i was given landmark ids[i].
	const std::vector<std::int32_t> ids = slam.assigned_ids().back();
	std::printf("           readings -> landmarks:");
	for (std::size_t i = 0; i < ids.size(); i++) std::printf(" %zu->%d", i, ids[i]);
	std::printf("\n");
}

void OnlineSlamApp::print_landmarks(swba::estimators::MrptSlidingWindow& slam)
{
	// Each landmark in the state with its marginal covariance (one factorisation of the window's system).
	const std::map<std::int32_t, swba::estimators::LandmarkEstimate> map = slam.landmark_estimates();
	double worst = 0;
	std::int32_t worst_id = -1;
	for (const auto& [id, l] : map)
		if (largest_std(l.covariance) > worst)
		{
			worst = largest_std(l.covariance);
			worst_id = id;
		}
	std::printf("landmark covariances: %zu landmarks, the least certain is %d (largest std %.4f m)\n", map.size(),
				worst_id, worst);
}
