#include <swba/problems/inertial_simulation.h>

#include <swba/core/lie.h>
#include <swba/core/manifold.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>

namespace swba::problems
{
ImuNoise imu_grade_noise(ImuGrade grade)
{
	ImuNoise n;
	if (grade == ImuGrade::Tactical)
	{
		n.accel_noise_density = 1e-3;
		n.gyro_noise_density = 1.5e-5;
		n.accel_random_walk = 1e-5;
		n.gyro_random_walk = 1e-7;
	}
	else
	{
		n.accel_noise_density = 0.019;
		n.gyro_noise_density = 0.015;
		n.accel_random_walk = 1e-4;
		n.gyro_random_walk = 1e-5;
	}
	return n;
}

Eigen::Vector2d imu_grade_initial_bias_sigma(ImuGrade grade)
{
	return grade == ImuGrade::Tactical ? Eigen::Vector2d(0.01, 5e-6) : Eigen::Vector2d(0.05, 0.005);
}

namespace
{
/** A path p(u) in the phase u, its first two derivatives, and the phase's rate and acceleration. */
struct PathPoint
{
	Eigen::Vector3d p, dp, ddp;
	double udot = 0, uddot = 0, u = 0;
};

PathPoint figure_eight(double t)
{
	const double W = 2 * M_PI / 20.0, A = 10, B = 5, h = 2, C = 1;
	PathPoint q;
	q.u = W * t;
	q.udot = W;
	const double u = q.u;
	q.p = {A * std::sin(u), B * std::sin(2 * u), h + C * std::sin(3 * u)};
	q.dp = {A * std::cos(u), 2 * B * std::cos(2 * u), 3 * C * std::cos(3 * u)};
	q.ddp = {-A * std::sin(u), -4 * B * std::sin(2 * u), -9 * C * std::sin(3 * u)};
	return q;
}

/** Phase rate Ω(1 − cos νt)²/4: the car stops (smoothly, zero rate and acceleration) every 2π/ν s. */
PathPoint car_drive(double t)
{
	const double W = 0.3, nu = 2 * M_PI / 15.0, A = 30, B = 15;
	PathPoint q;
	const double c = std::cos(nu * t), s = std::sin(nu * t);
	q.u = W / 4 * (1.5 * t - 2 * s / nu + std::sin(2 * nu * t) / (4 * nu));
	q.udot = W / 4 * (1 - c) * (1 - c);
	q.uddot = W * nu * (1 - c) * s / 2;
	const double u = q.u;
	q.p = {A * std::sin(u), B * std::sin(2 * u), 0.0};
	q.dp = {A * std::cos(u), 2 * B * std::cos(2 * u), 0.0};
	q.ddp = {-A * std::sin(u), -4 * B * std::sin(2 * u), 0.0};
	return q;
}

/** Body rate of R = Rz(ψ)·Ry(θ)·Rx(φ) from the Euler angles and their rates. */
Eigen::Vector3d zyx_body_rate(double roll, double pitch, double droll, double dpitch, double dyaw)
{
	const double sr = std::sin(roll), cr = std::cos(roll), sp = std::sin(pitch), cp = std::cos(pitch);
	return {droll - dyaw * sp, dpitch * cr + dyaw * cp * sr, -dpitch * sr + dyaw * cp * cr};
}
}  // namespace

Kinematics trajectory_kinematics(InertialTrajectoryKind kind, double t)
{
	const bool car = kind == InertialTrajectoryKind::Car;
	const PathPoint q = car ? car_drive(t) : figure_eight(t);
	Kinematics k;
	k.p = q.p;
	k.v = q.dp * q.udot;
	k.a = q.ddp * q.udot * q.udot + q.dp * q.uddot;
	// Heading along the path's horizontal tangent (never zero on these paths), whatever the speed.
	const double yaw = std::atan2(q.dp.y(), q.dp.x());
	const double dyaw_du = (q.dp.x() * q.ddp.y() - q.dp.y() * q.ddp.x()) / (q.dp.x() * q.dp.x() + q.dp.y() * q.dp.y());
	const double roll = car ? 0.0 : 0.2 * std::sin(2 * q.u), pitch = car ? 0.0 : 0.1 * std::cos(q.u);
	const double droll = car ? 0.0 : 0.4 * std::cos(2 * q.u) * q.udot, dpitch = car ? 0.0 : -0.1 * std::sin(q.u) * q.udot;
	k.R = mrpt::poses::CPose3D(0, 0, 0, yaw, pitch, roll).getRotationMatrix().asEigen();
	k.omega = zyx_body_rate(roll, pitch, droll, dpitch, dyaw_du * q.udot);
	return k;
}

ImuSample exact_imu(InertialTrajectoryKind kind, double t, const Eigen::Vector3d& gravity)
{
	const Kinematics k = trajectory_kinematics(kind, t);
	return {t, k.R.transpose() * (k.a - gravity), k.omega};
}

void InertialSimulationOptions::validate() const
{
	auto positive = [](double x, const char* name) {
		if (!(std::isfinite(x) && x > 0)) throw std::invalid_argument(std::string(name) + " must be positive");
	};
	positive(duration, "duration");
	positive(imu_rate, "imu_rate");
	// The data set is held in memory (truth and reading per IMU time, a few hundred bytes each).
	constexpr double kMaxImuReadings = 1e7;
	if (duration * imu_rate > kMaxImuReadings)
	{
		char n[32];
		std::snprintf(n, sizeof n, "%.3g", duration * imu_rate);
		throw std::invalid_argument(std::string("duration x imu_rate = ") + n +
									" IMU readings, more than 1e7 (about 28 h at 100 Hz): simulate a longer run as "
									"several logs");
	}
	auto divides = [this](double rate, const char* name) {
		if (!(std::isfinite(rate) && rate >= 0)) throw std::invalid_argument(std::string(name) + " must be >= 0");
		if (rate == 0) return;
		const double ratio = imu_rate / rate;
		if (rate > imu_rate || std::abs(ratio - std::round(ratio)) > 1e-9)
			throw std::invalid_argument(std::string(name) + " must divide imu_rate");
	};
	divides(pose_rate, "pose_rate");
	divides(odometry_rate, "odometry_rate");
	positive(pose_sigma_m, "pose_sigma_m");
	positive(pose_sigma_rad, "pose_sigma_rad");
	if (!(odometry_drift >= 0) || !(odometry_rotation_drift >= 0))
		throw std::invalid_argument("odometry drifts must be >= 0");
}

namespace
{
using Vector6 = Eigen::Matrix<double, 6, 1>;

class Gaussian
{
   public:
	Gaussian(std::uint64_t seed, std::uint64_t stream)
	{
		std::seed_seq seq{seed, stream};
		gen_.seed(seq);
	}
	/** Three draws in x, y, z order (sequenced: the order in which a constructor's arguments are evaluated
	 * is unspecified, and GCC and clang differ, which changed every simulated log between compilers). */
	Eigen::Vector3d vec(double sd)
	{
		const double x = n(), y = n(), z = n();
		return Eigen::Vector3d(x, y, z) * sd;
	}

   private:
	double n() { return dist_(gen_); }
	std::mt19937_64 gen_;
	std::normal_distribution<double> dist_;
};

/** T·PseudoExp([ρ, ω]) as a CPose3D. */
mrpt::poses::CPose3D perturbed(const mrpt::poses::CPose3D& T, const Vector6& d)
{
	double x[12], y[12];
	SE3Manifold::from_pose(T, x);
	SE3Manifold::instance()->plus(x, d.data(), y);
	return SE3Manifold::to_pose(y);
}

Eigen::Matrix<double, 6, 6> diagonal6(double st, double sr)
{
	Vector6 d;
	d << Eigen::Vector3d::Constant(st * st), Eigen::Vector3d::Constant(sr * sr);
	return d.asDiagonal();
}

mrpt::poses::CPose3D to_cpose(const Kinematics& k)
{
	mrpt::math::CMatrixDouble33 R;
	R.asEigen() = k.R;
	return mrpt::poses::CPose3D(R, mrpt::math::CVectorFixedDouble<3>({k.p.x(), k.p.y(), k.p.z()}));
}

void add_pose_measurements(const InertialSimulationOptions& o, InertialDataset& d)
{
	Gaussian pose_rng(o.seed, 2), odo_rng(o.seed, 3);
	const double f = o.noise_free ? 0.0 : 1.0;
	const int pose_every = o.pose_rate > 0 ? int(std::lround(o.imu_rate / o.pose_rate)) : 0;
	const int odo_every = o.odometry_rate > 0 ? int(std::lround(o.imu_rate / o.odometry_rate)) : 0;
	mrpt::poses::CPose3D odo, last_truth;
	for (size_t k = 0; k < d.truth.size(); k++)
	{
		const InertialTruth& x = d.truth[k];
		if (pose_every && k % pose_every == 0)
		{
			Vector6 n;
			n << pose_rng.vec(o.pose_sigma_m * f), pose_rng.vec(o.pose_sigma_rad * f);
			d.pose_priors.push_back({x.t, perturbed(x.pose, n), diagonal6(o.pose_sigma_m, o.pose_sigma_rad)});
		}
		if (odo_every && k % odo_every == 0)
		{
			if (d.odometry.empty())
			{
				odo = x.pose;
				d.odometry.push_back({x.t, odo, diagonal6(1e-3, 1e-4)});
			}
			else
			{
				const mrpt::poses::CPose3D D = x.pose - last_truth;  // last⁻¹ ⊕ now
				const double st = std::max(1e-3, o.odometry_drift * D.translation().norm());
				const double sr = std::max(1e-4, o.odometry_rotation_drift *
													  so3_log(D.getRotationMatrix().asEigen()).norm());
				Vector6 n;
				n << odo_rng.vec(st * f), odo_rng.vec(sr * f);
				odo = odo + perturbed(D, n);
				d.odometry.push_back({x.t, odo, diagonal6(st, sr)});
			}
			last_truth = x.pose;
		}
	}
}
}  // namespace

InertialDataset simulate_inertial(const InertialSimulationOptions& o)
{
	o.validate();
	InertialDataset d;
	d.noise = imu_grade_noise(o.grade);
	Gaussian imu_rng(o.seed, 1);
	const double f = o.noise_free ? 0.0 : 1.0;
	const double dt = 1.0 / o.imu_rate;
	const Eigen::Vector2d b0 = imu_grade_initial_bias_sigma(o.grade) * f;
	Vector6d bias;
	bias << imu_rng.vec(b0[0]), imu_rng.vec(b0[1]);
	const auto n = static_cast<std::size_t>(std::floor(o.duration * o.imu_rate + 1e-9)) + 1;
	for (std::size_t k = 0; k < n; k++)
	{
		const double t = k * dt;
		if (k > 0)
			bias += (Vector6d() << imu_rng.vec(d.noise.accel_random_walk * std::sqrt(dt) * f),
					 imu_rng.vec(d.noise.gyro_random_walk * std::sqrt(dt) * f))
						.finished();
		ImuSample s = exact_imu(o.trajectory, t, d.noise.gravity);
		s.acc += bias.head<3>() + imu_rng.vec(d.noise.accel_noise_density / std::sqrt(dt) * f);
		s.gyro += bias.tail<3>() + imu_rng.vec(d.noise.gyro_noise_density / std::sqrt(dt) * f);
		d.imu.push_back(s);
		const Kinematics kin = trajectory_kinematics(o.trajectory, t);
		d.truth.push_back({t, to_cpose(kin), kin.v, bias});
	}
	add_pose_measurements(o, d);
	return d;
}
}  // namespace swba::problems
