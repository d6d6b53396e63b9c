// What a fixed-lag estimator can reach: at keyframes k sampled every `stride`, the batch over the data up
// to keyframe k + W (the best estimate of keyframe k any estimator with a lag of W keyframes can make, in
// the window's own model) beside the window's lagged estimate of k (when it leaves at k + W) and the batch
// over all the data, APE translation rmse over the same keyframes. The window's lagged / batch ratio is
// bounded below by the lag optimum's (doc/inertial.md, "Measured").
//   swba_inertial_lag_bound [figure8|car] [consumer|tactical] [pose Hz] [odometry Hz] [W] [stride]
#include "inertial_bench.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

using namespace swba;
using namespace swba::estimators;
using namespace swba::problems;

namespace
{
/** Squared position error of the pose at time t of `tr` (exactly one must be there). */
double squared_error(const InertialTrajectory& tr, double t, const InertialDataset& d, double rate)
{
	for (std::size_t i = 0; i < tr.t.size(); i++)
		if (std::abs(tr.t[i] - t) < 1e-6) return bench::squared_position_error(tr.poses[i], t, d, rate);
	std::fprintf(stderr, "no estimate at t = %.6f\n", t);
	std::exit(1);
}
}  // namespace

int main(int argc, char** argv)
{
	InertialSimulationOptions s;
	if (argc > 1) s.trajectory = parse_enum<InertialTrajectoryKind>(argv[1], "trajectory");
	if (argc > 2) s.grade = parse_enum<ImuGrade>(argv[2], "grade");
	if (argc > 3) s.pose_rate = std::atof(argv[3]);
	if (argc > 4) s.odometry_rate = std::atof(argv[4]);
	const int W = argc > 5 ? std::atoi(argv[5]) : 30, stride = argc > 6 ? std::atoi(argv[6]) : 20;
	s.validate();
	bench::SimulatedInertialLog log = bench::simulate_inertial_log(s);
	const InertialDataset& d = log.data;
	const InertialInput& in = log.input;
	InertialWindowOptions& o = log.options;
	o.window_size = W;
	const InertialWindowResult w = run_inertial_window(in, o);
	const InertialTrajectory batch = run_inertial_batch(in, o);
	const std::vector<double> kf = w.lagged.t;
	double lag = 0, win = 0, all = 0;
	int n = 0;
	for (std::size_t k = static_cast<std::size_t>(stride); k + static_cast<std::size_t>(W) < kf.size();
		 k += static_cast<std::size_t>(stride))
	{
		const InertialTrajectory prefix = run_inertial_batch(inertial_input_until(in, kf[k + static_cast<std::size_t>(W)]), o);
		lag += squared_error(prefix, kf[k], d, s.imu_rate);
		win += squared_error(w.lagged, kf[k], d, s.imu_rate);
		all += squared_error(batch, kf[k], d, s.imu_rate);
		n++;
	}
	std::printf("%s %s, priors %g Hz, odometry %g Hz, W = %d, %d keyframes (every %d): lag optimum %.4f m, "
				"window lagged %.4f m, batch %.4f m; window lagged / batch %.2f, lag optimum / batch %.2f\n",
				argc > 1 ? argv[1] : "figure8", argc > 2 ? argv[2] : "consumer", s.pose_rate, s.odometry_rate, W, n,
				stride, std::sqrt(lag / n), std::sqrt(win / n), std::sqrt(all / n), std::sqrt(win / all),
				std::sqrt(lag / all));
	return 0;
}
