#include <swba/apps/inertial_simulate.h>

#include <swba/eval/trajectory.h>
#include <swba/io/observation_rawlog.h>

#include <Eigen/Geometry>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <ostream>
#include <stdexcept>

namespace swba::apps
{
namespace
{
/** MRPT time of t = 0 in every simulated rawlog (fixed, so that the files are reproducible). */
constexpr double kTimeOrigin = 1.7e9;

std::ofstream open_out(const std::string& path)
{
	std::ofstream f(path);
	if (!f) throw std::runtime_error("cannot write '" + path + "'");
	f << std::setprecision(12);
	return f;
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
	std::ofstream path = open_out(out.robot_path);
	path << "% x y z yaw pitch roll (m, rad): the true IMU pose at each pose-prior time\n";
	size_t j = 0;
	for (const auto& x : d.truth)
	{
		const bool row = d.pose_priors.empty() || (j < d.pose_priors.size() && std::abs(d.pose_priors[j].t - x.t) < 1e-9);
		if (!row) continue;
		j++;
		path << x.pose.x() << ' ' << x.pose.y() << ' ' << x.pose.z() << ' ' << x.pose.yaw() << ' ' << x.pose.pitch()
			 << ' ' << x.pose.roll() << '\n';
	}
	std::ofstream state = open_out(out.state);
	state << "# t x y z qx qy qz qw vx vy vz bax bay baz bgx bgy bgz (s, m, m/s, m/s^2, rad/s)\n";
	for (const auto& x : d.truth)
	{
		const Eigen::Quaterniond q(x.pose.getRotationMatrix().asEigen());
		state << x.t << ' ' << x.pose.x() << ' ' << x.pose.y() << ' ' << x.pose.z() << ' ' << q.x() << ' ' << q.y() << ' '
			  << q.z() << ' ' << q.w() << ' ' << x.v.transpose() << ' ' << x.bias.transpose() << '\n';
	}
}

void write_ini(const std::string& path, const problems::InertialDataset& d)
{
	std::ofstream f = open_out(path);
	f << "; roles of the simulated rawlog's sensors and the simulated IMU's noise\n[sensors]\nimu = "
	  << kSimulatedImuLabel << "\npose_prior = " << kSimulatedPosePriorLabel << "\nodometry = " << kSimulatedOdometryLabel
	  << "\n\n[imu]\n";
	for (const auto& k : ImuNoise::ini_keys("imu")) f << k.key << " = " << k.get(d.noise) << "\n";
}
}  // namespace

void InertialSimulateOptions::validate() const
{
	simulation.validate();
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
