#include <swba/apps/inertial_simulate.h>

#include <swba/core/file.h>
#include <swba/eval/trajectory.h>
#include <swba/io/observation_rawlog.h>

#include <Eigen/Geometry>
#include <filesystem>
#include <functional>
#include <iomanip>
#include <ostream>
#include <stdexcept>
#include <string>

namespace swba::apps
{
namespace
{
/** MRPT time of t = 0 in every simulated rawlog (fixed, so that the files are reproducible). */
constexpr double kTimeOrigin = 1.7e9;

/** Writes `path` through the atomic writer (swba/core/file.h) with 12 significant digits: a failed write
 * throws "cannot write '<path>': <OS reason>". */
void write_text_output(const std::string& path, const std::function<void(std::ostream&)>& write)
{
	write_file_atomically(path, [&](std::ostream& f) {
		f << std::setprecision(12);
		write(f);
	});
}

void write_rawlog(const std::string& path, const problems::InertialDataset& d)
{
	std::vector<mrpt::obs::CObservation::Ptr> objs;
	size_t ip = 0, io_ = 0;
	for (const auto& s : d.imu)
	{
		objs.push_back(io::make_imu_observation(kTimeOrigin, s.t, s.acc, s.gyro, kSimulatedImuLabel));
		for (; ip < d.pose_priors.size() && d.pose_priors[ip].t <= s.t + 1e-9; ip++)
		{
			const auto& z = d.pose_priors[ip];
			objs.push_back(io::make_pose_observation(kTimeOrigin, z.t, z.pose, io::ypr_covariance_from_tangent(z.pose, z.covariance),
													 kSimulatedPosePriorLabel));
		}
		for (; io_ < d.odometry.size() && d.odometry[io_].t <= s.t + 1e-9; io_++)
		{
			const auto& z = d.odometry[io_];
			const mrpt::poses::CPose3D increment = io_ == 0 ? z.pose : z.pose - d.odometry[io_ - 1].pose;
			objs.push_back(io::make_pose_observation(kTimeOrigin, z.t, z.pose,
													 io::ypr_covariance_from_tangent(increment, z.covariance),
													 kSimulatedOdometryLabel));
		}
	}
	io::write_observation_rawlog(path, objs);
}

void write_truth(const SimulatedInertialRawlog& out, const problems::InertialDataset& d)
{
	eval::Trajectory tum;
	for (const auto& x : d.truth) tum.push_back(x.t, x.pose);
	eval::write_tum(out.ground_truth, tum);
	write_text_output(out.robot_path, [&](std::ostream& path) {
		path << "% x y z yaw pitch roll (m, rad): the true IMU pose at each pose-prior time\n";
		size_t j = 0;
		for (const auto& x : d.truth)
		{
			const bool row =
					d.pose_priors.empty() || (j < d.pose_priors.size() && std::abs(d.pose_priors[j].t - x.t) < 1e-9);
			if (!row) continue;
			j++;
			path << x.pose.x() << ' ' << x.pose.y() << ' ' << x.pose.z() << ' ' << x.pose.yaw() << ' ' << x.pose.pitch()
				 << ' ' << x.pose.roll() << '\n';
		}
	});
	write_text_output(out.state, [&](std::ostream& state) {
		state << "# t x y z qx qy qz qw vx vy vz bax bay baz bgx bgy bgz (s, m, m/s, m/s^2, rad/s)\n";
		for (const auto& x : d.truth)
		{
			const Eigen::Quaterniond q(x.pose.getRotationMatrix().asEigen());
			state << x.t << ' ' << x.pose.x() << ' ' << x.pose.y() << ' ' << x.pose.z() << ' ' << q.x() << ' ' << q.y()
				  << ' ' << q.z() << ' ' << q.w() << ' ' << x.v.transpose() << ' ' << x.bias.transpose() << '\n';
		}
	});
}

void write_ini(const std::string& path, const problems::InertialDataset& d)
{
	write_text_output(path, [&](std::ostream& f) {
		// A role is named only when the rawlog holds it: swba run rejects a label no observation carries.
		f << "; roles of the simulated rawlog's sensors and the simulated IMU's noise\n[sensors]\nimu = "
		  << kSimulatedImuLabel << "\n";
		if (!d.pose_priors.empty()) f << "pose_prior = " << kSimulatedPosePriorLabel << "\n";
		if (!d.odometry.empty()) f << "odometry = " << kSimulatedOdometryLabel << "\n";
		f << "\n[imu]\n";
		for (const auto& k : ImuNoise::ini_keys("imu")) f << k.key << " = " << k.get(d.noise) << "\n";
	});
}
}  // namespace

void InertialSimulateOptions::validate() const
{
	simulation.validate();
	// swba run's keyframes are at the pose priors (at the odometry poses without priors): an IMU factor
	// between two of them needs an IMU reading strictly between (two integration steps).
	const bool priors = simulation.pose_rate > 0;
	const double keyframe_rate = priors ? simulation.pose_rate : simulation.odometry_rate;
	if (keyframe_rate > 0 && simulation.imu_rate / keyframe_rate < 2 - 1e-9)
		throw std::invalid_argument(std::string(priors ? "pose_rate" : "odometry_rate") +
									" must be at most imu_rate / 2: swba run needs an IMU reading between consecutive "
									"keyframes");
	if (out_dir.empty()) throw std::invalid_argument("out_dir must not be empty");
}

std::string InertialSimulateOptions::output_name() const
{
	if (!name.empty()) return name;
	return enum_name(simulation.trajectory) + "_" + enum_name(simulation.grade) + "_seed" + std::to_string(simulation.seed);
}

SimulatedInertialRawlog simulate_inertial_rawlog(const InertialSimulateOptions& o, std::ostream& log)
{
	o.validate();
	const problems::InertialDataset d = problems::simulate_inertial(o.simulation);
	std::filesystem::create_directories(o.out_dir);
	const std::string base = (std::filesystem::path(o.out_dir) / o.output_name()).string();
	SimulatedInertialRawlog out{base + ".rawlog", base + "_ground_truth.tum", base + "_ground_truth_robot_path.txt",
								base + "_ground_truth_state.txt", base + ".ini"};
	write_rawlog(out.rawlog, d);
	write_truth(out, d);
	write_ini(out.ini, d);
	log << "swba simulate-imu: " << d.imu.size() << " IMU readings, " << d.pose_priors.size() << " pose priors, "
		<< d.odometry.size() << " odometry poses -> " << out.rawlog << "\n";
	return out;
}
estimators::InertialInput simulated_inertial_input(const problems::InertialDataset& d)
{
	estimators::InertialInput in;
	in.imu = d.imu;
	for (const auto& z : d.pose_priors) in.pose_priors.push_back({z.t, kSimulatedPosePriorLabel, z.pose, z.covariance});
	for (const auto& z : d.odometry) in.odometry.push_back({z.t, kSimulatedOdometryLabel, z.pose, z.covariance});
	return in;
}
}  // namespace swba::apps
