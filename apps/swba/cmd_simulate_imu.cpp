// swba simulate-imu: an inertial observation-format rawlog with exact ground truth. Logic in
// swba/apps/inertial_simulate.h.
#include <swba/apps/inertial_simulate.h>

#include <cmath>
#include <iostream>
#include <sstream>

#include "cli.h"
#include "command.h"

namespace swba::app
{
namespace
{
const char* const kAbout =
		"Makes an inertial observation-format rawlog (CObservationIMU 'IMU', CObservationRobotPose 'MAP_MATCHING' "
		"pose priors and 'LIDAR_ODOMETRY' drifting odometry) from an analytic trajectory, deterministic per seed: "
		"DIR/NAME.rawlog, DIR/NAME_ground_truth.tum (every IMU time), DIR/NAME_ground_truth_robot_path.txt (MRPT "
		"format, one row per pose prior), DIR/NAME_ground_truth_state.txt (pose, velocity, biases) and DIR/NAME.ini "
		"(sensor roles and IMU noise for swba run).";

/** Throws UsageError naming the flags when the keyframe rate `flag` (--pose-rate, or --odometry-rate
 * without pose priors: swba run's default keyframes) leaves fewer than two IMU intervals between
 * keyframes: an IMU factor between two of them needs an IMU reading strictly between
 * (InertialSimulateOptions::validate checks the same by option name; this names the flags). */
void check_keyframe_rate(const problems::InertialSimulationOptions& s, TCLAP::ValueArg<double>* flag)
{
	const double rate = flag->getValue();
	if (!(std::isfinite(s.imu_rate) && s.imu_rate > 0) || !(rate > 0) || s.imu_rate / rate >= 2 - 1e-9) return;
	std::ostringstream m;  // an invalid --imu-rate is left to validate(), which names it
	m << "--" << flag->getName() << " " << rate << " with --imu-rate " << s.imu_rate
	  << " leaves fewer than two IMU intervals between keyframes, which swba run needs (an IMU reading between "
		 "them): give at most --imu-rate / 2 = "
	  << s.imu_rate / 2 << (flag->getName() == "pose-rate" ? ", or 0 for none" : "");
	throw UsageError(m.str());
}

int run_simulate_imu(int argc, char** argv)
{
	TCLAP::CmdLine cmd(kAbout, ' ', "0.1.0");
	using problems::ImuGrade;
	using problems::InertialTrajectoryKind;
	apps::InertialSimulateOptions o;
	auto& s = o.simulation;
	TCLAP::ValueArg<std::string> traj("", "trajectory", "figure8 (3-D) or car (planar, turns and stops) (Default: figure8)",
									  false, "figure8", enum_choices<InertialTrajectoryKind>("|"));
	TCLAP::ValueArg<std::string> grade("", "grade", "IMU grade (Default: consumer)", false, "consumer",
									   enum_choices<ImuGrade>("|"));
	TCLAP::ValueArg<double> duration("", "duration", "seconds (Default: 60)", false, s.duration, "S");
	TCLAP::ValueArg<double> imu_rate("", "imu-rate", "IMU rate, Hz (Default: 100)", false, s.imu_rate, "HZ");
	TCLAP::ValueArg<double> pose_rate("", "pose-rate", "pose-prior rate, Hz, dividing the IMU rate; 0 = none (Default: 10)",
									  false, s.pose_rate, "HZ");
	TCLAP::ValueArg<double> odo_rate("", "odometry-rate", "odometry rate, Hz, dividing the IMU rate; 0 = none (Default: 10)",
									 false, s.odometry_rate, "HZ");
	TCLAP::ValueArg<double> sigma_m("", "pose-sigma", "pose-prior sigma per axis, m (Default: 0.5)", false, s.pose_sigma_m, "M");
	TCLAP::ValueArg<double> sigma_deg("", "pose-sigma-deg", "pose-prior sigma per axis, degrees (Default: 1)", false, 1.0, "DEG");
	TCLAP::ValueArg<double> drift("", "odometry-drift", "odometry translation sigma per step / step length (Default: 0.01)",
								  false, s.odometry_drift, "F");
	TCLAP::ValueArg<double> rdrift("", "odometry-rotation-drift", "odometry rotation sigma per step / angle turned (Default: 0.01)",
								   false, s.odometry_rotation_drift, "F");
	TCLAP::SwitchArg noise_free("", "noise-free", "no IMU noise or bias, exact poses and odometry");
	TCLAP::ValueArg<unsigned long> seed("", "seed", "random seed (Default: 1)", false, 1, "S");
	TCLAP::ValueArg<std::string> out("", "out", "output directory, created (Default: .)", false, ".", "DIR");
	TCLAP::ValueArg<std::string> name("", "name", "base name (Default: <trajectory>_<grade>_seed<S>)", false, "", "NAME");
	for (TCLAP::Arg* a : std::initializer_list<TCLAP::Arg*>{&traj, &grade, &duration, &imu_rate, &pose_rate, &odo_rate,
															 &sigma_m, &sigma_deg, &drift, &rdrift, &noise_free, &seed, &out, &name})
		cmd.add(*a);
	if (auto rc = parse_command_line(cmd, argc, argv)) return *rc;
	try
	{
		s.trajectory = parse_enum<InertialTrajectoryKind>(traj.getValue(), "trajectory");
		s.grade = parse_enum<ImuGrade>(grade.getValue(), "IMU grade");
		s.duration = duration.getValue();
		s.imu_rate = imu_rate.getValue();
		s.pose_rate = pose_rate.getValue();
		s.odometry_rate = odo_rate.getValue();
		s.pose_sigma_m = sigma_m.getValue();
		s.pose_sigma_rad = sigma_deg.getValue() * M_PI / 180.0;
		s.odometry_drift = drift.getValue();
		s.odometry_rotation_drift = rdrift.getValue();
		s.noise_free = noise_free.getValue();
		s.seed = seed.getValue();
		o.out_dir = out.getValue();
		o.name = name.getValue();
		check_keyframe_rate(s, s.pose_rate > 0 ? &pose_rate : &odo_rate);
		o.validate();
	}
	catch (const std::invalid_argument& e)
	{
		throw UsageError(e.what());
	}
	const apps::SimulatedInertialRawlog r = apps::simulate_inertial_rawlog(o, std::cerr);
	std::cout << r.rawlog << "\n";
	return 0;
}
SWBA_REGISTER_COMMAND("simulate-imu", "an inertial rawlog (IMU, pose priors, odometry) with exact ground truth",
					  run_simulate_imu);
}  // namespace
}  // namespace swba::app
