// Runs of the error-state Kalman filter over an inertial input, and odometry dead reckoning
// (swba/estimators/inertial_filter.h).
#include <swba/estimators/inertial_filter.h>

#include <algorithm>
#include <stdexcept>
#include <tuple>

namespace swba::estimators
{
namespace
{
/** A measurement or report at a time; at equal times: odometry, then prior, then report. */
struct Event
{
	double t;
	int kind;  ///< 0 odometry, 1 prior, 2 report
	std::size_t index;
	bool operator<(const Event& o) const { return std::tie(t, kind, index) < std::tie(o.t, o.kind, o.index); }
};

void record(InertialTrajectory& out, double t, const ErrorStateKalmanFilter& f)
{
	out.t.push_back(t);
	out.poses.push_back(f.pose());
	out.velocities.push_back(f.state().v);
	out.biases.push_back(f.bias());
	out.pose_covariances.push_back(f.pose_covariance());
}

std::vector<Event> filter_events(const InertialInput& in, const InertialFilterOptions& o, double t0)
{
	std::vector<Event> ev;
	if (o.use_odometry)
		for (std::size_t i = 0; i < in.odometry.size(); i++)
			if (in.odometry[i].t >= t0) ev.push_back({in.odometry[i].t, 0, i});
	// The first prior made the initial state: it is not used again.
	if (o.use_pose_priors)
		for (std::size_t i = 1; i < in.pose_priors.size(); i++)
			if (in.pose_priors[i].t >= t0) ev.push_back({in.pose_priors[i].t, 1, i});
	const std::vector<double> reports = inertial_report_times(in, o.keyframes);
	for (std::size_t i = 0; i < reports.size(); i++)
		if (reports[i] >= t0) ev.push_back({reports[i], 2, i});
	std::sort(ev.begin(), ev.end());
	return ev;
}

void check_single_odometry_label(const InertialInput& in)
{
	for (const auto& r : in.odometry)
		if (r.label != in.odometry.front().label)
			throw std::invalid_argument("inertial input: odometry from several labels ('" + in.odometry.front().label +
										"', '" + r.label + "'); one odometry is supported");
}
}  // namespace

InertialInput inertial_input_until(const InertialInput& in, double t)
{
	InertialInput out;
	auto until = [t](const auto& readings) {  // readings in time order
		const auto end = std::upper_bound(readings.begin(), readings.end(), t,
										  [](double x, const auto& r) { return x < r.t; });
		return std::vector(readings.begin(), end);
	};
	out.imu = until(in.imu);
	out.pose_priors = until(in.pose_priors);
	out.odometry = until(in.odometry);
	return out;
}

std::vector<double> inertial_report_times(const InertialInput& in, KeyframeTimes keyframes)
{
	std::vector<double> t;
	for (const auto& r : (in.pose_priors.empty() ? in.odometry : in.pose_priors)) t.push_back(r.t);
	if (keyframes == KeyframeTimes::PosePriors || in.pose_priors.empty()) return t;
	for (const auto& r : in.odometry) t.push_back(r.t);
	std::sort(t.begin(), t.end());
	std::vector<double> merged;
	for (double x : t)
		if (merged.empty() || x - merged.back() >= 1e-6) merged.push_back(x);
	return merged;
}

InertialTrajectory run_inertial_filter(const InertialInput& in, const InertialFilterOptions& o)
{
	check_single_odometry_label(in);
	const InertialInitialState init = initial_inertial_state(in, o.prior);
	ErrorStateKalmanFilter f(o.noise, init);
	InertialTrajectory out;
	const std::vector<Event> ev = filter_events(in, o, init.t);
	// The reading at t0, interpolated between the readings around it.
	std::size_t k = 0;
	while (k + 1 < in.imu.size() && in.imu[k + 1].t <= init.t) k++;
	ImuSample cur = interpolate_imu(in.imu[k], in.imu[std::min(k + 1, in.imu.size() - 1)], init.t);
	std::size_t e = 0;
	const mrpt::poses::CPose3D* last_odometry = nullptr;
	for (std::size_t next = k + 1; next <= in.imu.size(); next++)
	{
		const bool last = next == in.imu.size();
		while (e < ev.size() && (last || ev[e].t <= in.imu[next].t))
		{
			if (ev[e].t > cur.t)
			{
				if (last) break;  // past the last reading
				const ImuSample s = interpolate_imu(cur, in.imu[next], ev[e].t);
				f.propagate(cur, s);
				out.imu_steps++;
				cur = s;
			}
			const Event& x = ev[e++];
			if (x.kind == 0)
			{
				const io::PoseReading& z = in.odometry[x.index];
				if (f.has_clone() && last_odometry) f.update_relative(z.pose - *last_odometry, z.covariance);
				f.clone_pose();
				last_odometry = &z.pose;
			}
			else if (x.kind == 1)
				f.update_pose(in.pose_priors[x.index].pose, in.pose_priors[x.index].covariance);
			else
				record(out, x.t, f);
		}
		if (last) break;
		if (in.imu[next].t > cur.t)
		{
			f.propagate(cur, in.imu[next]);
			out.imu_steps++;
		}
		cur = in.imu[next];
	}
	return out;
}

InertialTrajectory run_odometry_dead_reckoning(const InertialInput& in, const InertialPriorOptions& prior,
											   const std::vector<double>& report_times)
{
	check_single_odometry_label(in);
	if (in.odometry.empty()) throw std::invalid_argument("odometry dead reckoning: no odometry");
	const InertialInitialState init = initial_inertial_state(in, prior);
	const mrpt::poses::CPose3D T0(mrpt::math::CMatrixDouble44(
		(Eigen::Matrix4d() << init.x.R, init.x.p, 0, 0, 0, 1).finished()));
	std::size_t a = 0;	// the odometry reading the chain starts from: the latest at or before t0
	while (a + 1 < in.odometry.size() && in.odometry[a + 1].t <= init.t) a++;
	InertialTrajectory out;
	std::size_t j = a;
	for (double t : report_times)
	{
		if (t < init.t) continue;
		while (j + 1 < in.odometry.size() && in.odometry[j + 1].t <= t) j++;
		out.t.push_back(t);
		out.poses.push_back(T0 + (in.odometry[j].pose - in.odometry[a].pose));
		out.velocities.push_back(Eigen::Vector3d::Zero());
		out.biases.push_back(Vector6d::Zero());
		out.pose_covariances.push_back(Matrix6d::Zero());
	}
	return out;
}
}  // namespace swba::estimators
