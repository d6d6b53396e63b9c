// swba run on an inertial rawlog (run_inertial_app, through run_app where the command goes that way) and
// swba simulate-imu: bad input named before any estimator runs (labels that match nothing, a pose that is
// not finite, keyframes without an IMU reading between them, a ground truth whose stamps match no
// keyframe), write errors named, a stop request honoured between estimators, the options that do not
// apply named.
#include <swba/apps/inertial_run.h>
#include <swba/apps/inertial_simulate.h>
#include <swba/apps/run.h>
#include <swba/apps/run_options.h>
#include <swba/io/observation_rawlog.h>

#include <mrpt/obs/CObservationRobotPose.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "test_temp_dir.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

namespace
{
namespace fs = std::filesystem;
using swba::apps::RunOptions;

/** A 3 s simulated figure-eight (IMU 100 Hz, priors and odometry 10 Hz) in `dir`, the simulator's files. */
swba::apps::SimulatedInertialRawlog simulate_short_inertial_log(const fs::path& dir)
{
	swba::apps::InertialSimulateOptions o;
	o.simulation.duration = 3;
	o.out_dir = dir.string();
	o.name = "imu";
	std::ostringstream log;
	return swba::apps::simulate_inertial_rawlog(o, log);
}

/** Options for a quick inertial run on `rawlog` into dir/out: W = 5, no batch, no plots, the roles of the
 * simulator's .ini. */
RunOptions quick_inertial_options(const fs::path& dir, const std::string& rawlog)
{
	RunOptions o;
	o.rawlog = rawlog;
	o.out_dir = (dir / "out").string();
	o.windows = {5};
	o.run_batch = false;
	o.plots = false;
	o.progress = false;
	o.sensors.imu = {swba::apps::kSimulatedImuLabel};
	o.sensors.pose_prior = {swba::apps::kSimulatedPosePriorLabel};
	o.sensors.odometry = {swba::apps::kSimulatedOdometryLabel};
	return o;
}

/** The message of what `f` throws as std::runtime_error ("" when it does not throw). */
template <class F>
std::string runtime_error_of(F f)
{
	try
	{
		f();
	}
	catch (const std::runtime_error& e)
	{
		return e.what();
	}
	return "";
}

/** Writes an observation rawlog: IMU readings of the simulation `d` (its labels) and a pose prior at each
 * of `pose_times` (the true pose, σ 0.5 m / 0.02 rad), the one at index `nan_pose` (if any) with a NaN x. */
void write_inertial_rawlog(const std::string& path, const swba::problems::InertialDataset& d,
						   const std::vector<double>& pose_times, std::size_t nan_pose = std::size_t(-1))
{
	constexpr double origin = 1.7e9;
	Eigen::Matrix<double, 6, 6> cov = Eigen::Matrix<double, 6, 6>::Identity() * 0.25;
	cov.bottomRightCorner<3, 3>() = Eigen::Matrix3d::Identity() * 4e-4;
	std::vector<mrpt::obs::CObservation::Ptr> objs;
	std::size_t p = 0;
	for (std::size_t k = 0; k < d.imu.size(); k++)
	{
		const auto& s = d.imu[k];
		objs.push_back(swba::io::make_imu_observation(origin, s.t, s.acc, s.gyro, swba::apps::kSimulatedImuLabel));
		for (; p < pose_times.size() && pose_times[p] <= s.t + 1e-9; p++)
		{
			mrpt::poses::CPose3D pose = d.truth[k].pose;
			if (p == nan_pose) pose.x(std::numeric_limits<double>::quiet_NaN());
			auto o = swba::io::make_pose_observation(origin, s.t, d.truth[k].pose, cov, swba::apps::kSimulatedPosePriorLabel);
			o->pose.mean = pose;
			objs.push_back(o);
		}
	}
	swba::io::write_observation_rawlog(path, objs);
}

swba::problems::InertialDataset simulated_dataset(double duration)
{
	swba::problems::InertialSimulationOptions so;
	so.duration = duration;
	return swba::problems::simulate_inertial(so);
}

std::vector<double> every_imu_time(const swba::problems::InertialDataset& d, std::size_t stride)
{
	std::vector<double> t;
	for (std::size_t k = 0; k < d.imu.size(); k += stride) t.push_back(d.imu[k].t);
	return t;
}
}  // namespace

TEST(InertialRun, WriteErrorOfTheSummaryNamesTheFileAndTheReason)
{
	if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
	const auto d = temp_dir();
	const auto sim = simulate_short_inertial_log(d);
	RunOptions o = quick_inertial_options(d, sim.rawlog);
	fs::create_directories(o.out_dir);
	const std::string summary = o.out_dir + "/summary.json";
	fs::create_symlink("/dev/full", summary);
	std::ostringstream out, log;
	EXPECT_EQ(runtime_error_of([&] { swba::apps::run_app(o, out, log); }),
			  "cannot write '" + summary + "': No space left on device");
}

TEST(InertialRun, WriteErrorOfTheSimulatorNamesTheFileAndTheReason)
{
	if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
	const auto d = temp_dir();
	for (const std::string suffix : {".rawlog", ".ini", "_ground_truth_state.txt", "_ground_truth_robot_path.txt"})
	{
		const fs::path dir = d / ("full" + suffix);
		fs::create_directories(dir);
		fs::create_symlink("/dev/full", dir / ("imu" + suffix));
		EXPECT_EQ(runtime_error_of([&] { simulate_short_inertial_log(dir); }),
				  "cannot write '" + (dir / ("imu" + suffix)).string() + "': No space left on device");
	}
}

TEST(InertialRun, StopRequestBetweenEstimatorsMarksTheRestInterrupted)
{
	const auto d = temp_dir();
	const auto sim = simulate_short_inertial_log(d);
	RunOptions o = quick_inertial_options(d, sim.rawlog);
	o.run_batch = true;
	int polls = 0;
	std::ostringstream out, log;
	// Polled before each estimator: ESKF, IMU only, odometry only, window W=5, batch. Stop before the window.
	const auto rep = swba::apps::run_inertial_app(o, out, log, [&] { return ++polls > 3; });
	EXPECT_TRUE(swba::apps::run_interrupted(rep));
	ASSERT_EQ(rep.rows.size(), 6u);
	for (std::size_t i = 0; i < 3; i++)
	{
		EXPECT_FALSE(rep.rows[i].interrupted) << rep.rows[i].label;
		EXPECT_TRUE(rep.rows[i].has_ape) << rep.rows[i].label;
	}
	for (std::size_t i = 3; i < 6; i++)
	{
		EXPECT_TRUE(rep.rows[i].interrupted) << rep.rows[i].label;
		EXPECT_EQ(rep.rows[i].failed_step, 0u) << rep.rows[i].label;
	}
	EXPECT_NE(out.str().find("window W=5 lagged"), std::string::npos) << out.str();
	EXPECT_NE(out.str().find("INTERRUPTED after 0 steps"), std::string::npos) << out.str();
	const auto j = nlohmann::json::parse(slurp(fs::path(o.out_dir) / "summary.json"));
	ASSERT_EQ(j.at("rows").size(), 6u);
	EXPECT_FALSE(j["rows"][0].at("interrupted").get<bool>());
	EXPECT_EQ(j["rows"][0].at("file"), "eskf.tum");
	for (std::size_t i = 3; i < 6; i++)
	{
		EXPECT_TRUE(j["rows"][i].at("interrupted").get<bool>()) << i;
		EXPECT_TRUE(j["rows"][i].at("file").is_null()) << i;
	}
	EXPECT_TRUE(fs::exists(fs::path(o.out_dir) / "eskf.tum"));
	EXPECT_FALSE(fs::exists(fs::path(o.out_dir) / "window_W_5.tum"));
}

TEST(InertialRun, GroundTruthMatchingSomePosesIsNotedAndNoneIsAnError)
{
	const auto d = temp_dir();
	const auto sim = simulate_short_inertial_log(d);
	const auto gt = swba::eval::read_tum(sim.ground_truth);
	// The truth up to t = 1.5 s only: 16 of the 31 keyframes (t = 0, 0.1, ..., 3) match.
	swba::eval::Trajectory half, shifted;
	for (std::size_t i = 0; i < gt.size(); i++)
	{
		if (gt.stamps[i] <= 1.5 + 1e-9) half.push_back(gt.stamps[i], gt.poses[i]);
		shifted.push_back(gt.stamps[i] + 1700000000.0, gt.poses[i]);  // Unix time: matches nothing
	}
	const std::string half_path = (d / "half.tum").string(), shifted_path = (d / "shifted.tum").string();
	swba::eval::write_tum(half_path, half);
	swba::eval::write_tum(shifted_path, shifted);

	RunOptions o = quick_inertial_options(d, sim.rawlog);
	o.ground_truth = half_path;
	std::ostringstream out, log;
	const auto rep = swba::apps::run_inertial_app(o, out, log);
	ASSERT_EQ(rep.notes.size(), 1u) << log.str();
	EXPECT_EQ(rep.notes[0].rfind("APE over 16 of 31 poses", 0), 0u) << rep.notes[0];
	EXPECT_NE(rep.notes[0].find(half_path), std::string::npos) << rep.notes[0];
	EXPECT_NE(rep.notes[0].find("eskf, imu only, odometry only, window W=5, window W=5 lagged"), std::string::npos)
			<< rep.notes[0];
	EXPECT_NE(log.str().find("note: APE over 16 of 31 poses"), std::string::npos) << log.str();
	EXPECT_EQ(rep.rows[0].ape_trans.count, 16u);

	o.ground_truth = shifted_path;
	const std::string e = runtime_error_of([&] { swba::apps::run_inertial_app(o, out, log); });
	EXPECT_EQ(e.rfind("ground truth '" + shifted_path + "': found no matching time stamps between the ground truth (301 "
					  "poses, t = 1.7e+09 .. 1.7e+09) and the rawlog's keyframes (31 poses, t = 0 .. 3",
					  0),
			  0u)
			<< e;
	// The full truth: every pose matches, no note (the reference runs print none).
	o.ground_truth = sim.ground_truth;
	EXPECT_TRUE(swba::apps::run_inertial_app(o, out, log).notes.empty());
}

TEST(InertialRun, KeyframesWithoutAnImuReadingBetweenThemAreAnInputError)
{
	const auto d = temp_dir();
	const auto data = simulated_dataset(1);
	const std::string path = (d / "fast_poses.rawlog").string();
	write_inertial_rawlog(path, data, every_imu_time(data, 1));  // a pose prior at every IMU reading
	RunOptions o = quick_inertial_options(d, path);
	o.sensors.odometry.clear();
	std::ostringstream out, log;
	const std::string e = runtime_error_of([&] { swba::apps::run_inertial_app(o, out, log); });
	EXPECT_EQ(e.rfind("rawlog '" + path + "': the keyframe at t = 0.01 s has 0 IMU readings between it and the previous "
					  "keyframe (t = 0 s)",
					  0),
			  0u)
			<< e;
	EXPECT_FALSE(fs::exists(o.out_dir)) << "checked before the output directory is made";
	// One reading between: two integration steps, the run completes.
	write_inertial_rawlog(path, data, every_imu_time(data, 2));
	EXPECT_NO_THROW(swba::apps::run_inertial_app(o, out, log)) << log.str();

	swba::apps::InertialSimulateOptions so;
	so.simulation.pose_rate = 100;
	EXPECT_THROW(so.validate(), std::invalid_argument);
	so.simulation.pose_rate = 0;
	so.simulation.odometry_rate = 100;
	EXPECT_THROW(so.validate(), std::invalid_argument);
	so.simulation.pose_rate = 10;  // keyframes at the priors: fast odometry is composed between them
	EXPECT_NO_THROW(so.validate());
}

TEST(InertialRun, PoseThatIsNotFiniteNamesTheFileEntryAndLabel)
{
	const auto d = temp_dir();
	const auto data = simulated_dataset(1);
	const std::string path = (d / "nan_pose.rawlog").string();
	write_inertial_rawlog(path, data, every_imu_time(data, 10), 3);
	const std::string e = runtime_error_of([&] { swba::io::read_observation_rawlog(path); });
	// Entries: IMU at 0, pose 0, IMU x 10, pose 1, ...: pose 3 is entry 3 * 11 + 1.
	EXPECT_EQ(e.rfind("rawlog '" + path + "': entry 34: pose of '" + swba::apps::kSimulatedPosePriorLabel +
						  "' is not finite",
					  0),
			  0u)
			<< e;
}

TEST(InertialRun, SensorLabelsThatMatchNothingAreNamedWithTheRawlogsLabels)
{
	const auto d = temp_dir();
	const auto sim = simulate_short_inertial_log(d);
	swba::io::SensorRoles roles;
	roles.pose_prior = {"NOPE"};
	roles.odometry = {swba::apps::kSimulatedOdometryLabel};
	const std::string held = "(the rawlog holds CObservationIMU 'IMU'; CObservationRobotPose 'LIDAR_ODOMETRY', "
							 "'MAP_MATCHING')";
	EXPECT_EQ(runtime_error_of([&] { swba::io::read_observation_rawlog(sim.rawlog, roles); }),
			  "rawlog '" + sim.rawlog + "': [sensors] pose_prior = NOPE: no CObservationRobotPose has that label " + held);
	roles.pose_prior = {swba::apps::kSimulatedPosePriorLabel};
	roles.imu = {"XSENS"};
	EXPECT_EQ(runtime_error_of([&] { swba::io::read_observation_rawlog(sim.rawlog, roles); }),
			  "rawlog '" + sim.rawlog + "': [sensors] imu = XSENS: no CObservationIMU has that label " + held);
	roles.imu = {swba::apps::kSimulatedImuLabel};
	EXPECT_NO_THROW(swba::io::read_observation_rawlog(sim.rawlog, roles));
}

TEST(InertialRun, RangeBearingOptionsAreNamedAsIgnored)
{
	const auto d = temp_dir();
	const auto sim = simulate_short_inertial_log(d);
	RunOptions o = quick_inertial_options(d, sim.rawlog);
	o.window.gauge = swba::GaugeMode::Free;
	o.window.landmarks = swba::estimators::LandmarkParameterization::Xyz;
	o.window.gate_readings = true;
	o.window.gate_probability = 0.9;
	o.window.robust_loss = swba::RobustLoss::Huber;
	o.window.robust_probability = 0.9;
	o.window.sensor.std_range = 0.1;
	o.window.sensor.std_yaw = 0.01;
	o.window.sensor.std_pitch = 0.01;
	o.window.relinearized_poses = 3;
	o.window.association = swba::estimators::DataAssociation::NearestNeighbour;
	o.verbose = true;
	std::ostringstream out, log;
	swba::apps::run_app(o, out, log);
	const std::string warning = log.str().substr(log.str().find("swba run: warning: not used on an inertial rawlog"));
	for (const char* flag : {"--gauge (the inertial window's is [inertial] gauge)", "--landmarks", "--gate,",
							 "--gate-probability", "--robust-loss", "--robust-probability", "--sensor-std-range",
							 "--sensor-std-yaw-deg", "--sensor-std-pitch-deg", "--relinearized-poses", "--association",
							 "--verbose"})
		EXPECT_NE(warning.find(flag), std::string::npos) << flag << "\n" << warning;
	// The defaults: no warning.
	std::ostringstream log2;
	swba::apps::run_app(quick_inertial_options(d, sim.rawlog), out, log2);
	EXPECT_EQ(log2.str().find("warning"), std::string::npos) << log2.str();
}

TEST(InertialRun, TheSimulatorsIniRunsWithEitherKeyframeSourceAlone)
{
	// The .ini names only the roles the rawlog holds: a label no observation carries is an error of swba run.
	for (const bool priors : {true, false})
	{
		const auto d = temp_dir() / (priors ? "priors_only" : "odometry_only");
		swba::apps::InertialSimulateOptions so;
		so.simulation.duration = 3;
		(priors ? so.simulation.odometry_rate : so.simulation.pose_rate) = 0;
		so.out_dir = d.string();
		so.name = "imu";
		std::ostringstream sim_log;
		const auto sim = swba::apps::simulate_inertial_rawlog(so, sim_log);
		const std::string ini = slurp(sim.ini);
		EXPECT_EQ(ini.find("odometry =") == std::string::npos, priors) << ini;
		EXPECT_EQ(ini.find("pose_prior =") == std::string::npos, !priors) << ini;
		RunOptions o;
		swba::apps::load_run_config(sim.ini, o);
		o.rawlog = sim.rawlog;
		o.out_dir = (d / "out").string();
		o.windows = {5};
		o.run_batch = false;
		o.plots = false;
		o.progress = false;
		std::ostringstream out, log;
		const auto rep = swba::apps::run_app(o, out, log);
		ASSERT_FALSE(rep.rows.empty());
		for (const auto& r : rep.rows) EXPECT_FALSE(r.failed) << r.name << "\n" << log.str();
	}
}
