// Cost of the inertial estimators on simulated logs: for each IMU rate, the filter's time per IMU reading
// and the window's time per keyframe (update, marginalisation, covariance of the newest pose) for
// W = 10, 20, 30, with the real-time factor (keyframe period / time per keyframe) and APE beside it.
#include "inertial_bench.h"

#include <swba/core/timing.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

using namespace swba;
using namespace swba::estimators;

namespace
{
double rmse(const InertialTrajectory& tr, const problems::InertialDataset& d, double rate)
{
	double s = 0;
	for (std::size_t i = 0; i < tr.t.size(); i++) s += bench::squared_position_error(tr.poses[i], tr.t[i], d, rate);
	return std::sqrt(s / tr.t.size());
}

double percentile(std::vector<double> v, double p)
{
	std::sort(v.begin(), v.end());
	return v[static_cast<std::size_t>(p * (v.size() - 1))];
}
}  // namespace

int main()
{
	std::printf("%-8s %6s %-22s %12s %12s %12s %10s\n", "log", "IMU Hz", "estimator", "mean ms", "p95 ms",
				"real-time x", "APE m");
	for (double rate : {100.0, 400.0})
	{
		problems::InertialSimulationOptions s;
		s.imu_rate = rate;
		s.duration = 60;
		bench::SimulatedInertialLog log = bench::simulate_inertial_log(s);
		const problems::InertialDataset& d = log.data;
		const InertialInput& in = log.input;
		InertialWindowOptions& o = log.options;
		const auto t0 = SteadyClock::now();
		const InertialTrajectory f = run_inertial_filter(in, o.measurements);
		const double sec = seconds_since(t0);
		const double per_reading = sec / f.imu_steps;
		std::printf("%-8s %6.0f %-22s %12.5f %12s %12.0f %10.4f\n", "figure8", rate, "eskf (per IMU reading)",
					1e3 * per_reading, "-", (1.0 / rate) / per_reading, rmse(f, d, rate));
		for (int W : {10, 20, 30})
		{
			o.window_size = W;
			const InertialWindowResult w = run_inertial_window(in, o);
			std::vector<double> ms;
			for (double x : w.seconds_per_keyframe) ms.push_back(1e3 * x);
			double mean = 0;
			for (double x : ms) mean += x / ms.size();
			const double period_ms = 1e3 / s.pose_rate;
			std::printf("%-8s %6.0f %-22s %12.3f %12.3f %12.1f %10.4f\n", "figure8", rate,
						("window W=" + std::to_string(W)).c_str(), mean, percentile(ms, 0.95), period_ms / mean,
						rmse(w.online, d, rate));
		}
	}
	return 0;
}
