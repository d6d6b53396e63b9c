// What a fixed-lag estimator of the range-bearing model can reach on a rawlog: the lag-L optimum — the
// full-history solution after step k + L, read at step k (L = 0: the causal optimum) — beside the window's
// estimate of step k at the same lag (online for L = 0, lagged for L = W) and the batch (the better of its
// two starts, as `swba run` picks it), APE translation rmse (not aligned) over the same steps. No
// estimator that has seen the data up to k + L only, in this model with these options, is expected below
// the lag optimum; the window's figure against the batch is bounded below by the lag optimum's
// (doc/realdata.md, "Before and after"; with a mis-declared noise: doc/benchmarks/realdata.md). Default
// options are `swba run`'s.
//   swba_window_lag_bound RAWLOG [W] [relinearized poses] [sensor std range (m)] [sensor std yaw (deg)]
// O(steps²) (the full-history solve after every step): minutes on the real logs.
#include <swba/apps/run_options.h>
#include <swba/estimators/sliding_window.h>
#include <swba/eval/ground_truth.h>
#include <swba/eval/metrics.h>
#include <swba/io/rawlog.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <map>
#include <stdexcept>
#include <string>

using namespace swba;

namespace
{
using PoseByStamp = std::map<double, mrpt::poses::CPose3D>;

PoseByStamp by_stamp(const eval::Trajectory& t)
{
	PoseByStamp m;
	for (std::size_t i = 0; i < t.size(); i++) m[t.stamps[i]] = t.poses[i];
	return m;
}

/** Command-line argument `s` as a finite number >= 0 (the whole text), or std::invalid_argument naming
 * `what`: a typo must not silently become 0 (which means "the observation's own" for the sensor std). */
double non_negative_arg(const char* s, const char* what)
{
	char* end = nullptr;
	const double v = std::strtod(s, &end);
	if (end == s || *end != '\0' || !std::isfinite(v) || v < 0)
		throw std::invalid_argument(std::string(what) + " must be a number >= 0, got '" + s + "'");
	return v;
}

/** Command-line argument `s` as a whole number >= 0, or std::invalid_argument naming `what`. */
int count_arg(const char* s, const char* what)
{
	const double v = non_negative_arg(s, what);
	if (v != std::floor(v) || v > 1e6)
		throw std::invalid_argument(std::string(what) + " must be a whole number, got '" + s + "'");
	return static_cast<int>(v);
}

/** APE translation rmse of `of` at the stamps of `at` (each must be in `of`). */
double rmse_at(const std::vector<mrpt::poses::CPose3D>& gt, const eval::Trajectory& at, const PoseByStamp& of)
{
	eval::Trajectory t;
	for (double s : at.stamps) t.push_back(s, of.at(s));
	return eval::compute_statistics(eval::ape_errors_against_ground_truth(gt, t, eval::PoseRelation::TranslationPart)).rmse;
}

/** The full-history solution after each step, read at lags 0 and W: {causal optimum, lag-W optimum}. */
std::pair<eval::Trajectory, eval::Trajectory> lag_optima(const io::Rawlog& rawlog, estimators::SlidingWindowOptions o,
														 std::size_t W)
{
	o.window_size = 0;
	o.covariances = false;
	estimators::SlidingWindowEstimator full(o);
	eval::Trajectory causal, lagged;
	for (const auto& step : rawlog.steps)
	{
		full.process(step);
		const auto poses = full.window_poses();  // oldest first, the initial pose (t = 0) included
		causal.push_back(poses.back().first, poses.back().second);
		if (poses.size() > W + 1) lagged.push_back(poses[poses.size() - 1 - W].first, poses[poses.size() - 1 - W].second);
		if (step.index % 200 == 0) std::fprintf(stderr, "\rfull-history solve after step %zu", step.index);
	}
	std::fprintf(stderr, "\n");
	return {causal, lagged};
}

/** The batch from dead reckoning and from `start`; the one with the lower final cost. */
eval::Trajectory better_batch(const io::Rawlog& rawlog, estimators::SlidingWindowOptions o, int iterations,
							  const eval::Trajectory& start)
{
	o.window_size = 0;
	o.covariances = false;
	const estimators::BatchResult dr = estimators::run_batch(rawlog, o, iterations);
	const estimators::BatchResult ws = estimators::run_batch(rawlog, o, iterations, &start);
	return ws.summary.final_cost < dr.summary.final_cost ? ws.trajectory : dr.trajectory;
}
}  // namespace

int main(int argc, char** argv)
try
{
	if (argc < 2 || std::string(argv[1]) == "-h" || std::string(argv[1]) == "--help")
	{
		std::fprintf(argc < 2 ? stderr : stdout,
					 "usage: swba_window_lag_bound RAWLOG [W (30)] [relinearized poses (swba run's)] [sensor std range (m)] "
					 "[sensor std yaw (deg)] (0: the observation's own, as swba run's --sensor-std-*)\n");
		return argc < 2 ? 2 : 0;
	}
	const std::string path = argv[1];
	const int W = argc > 2 ? count_arg(argv[2], "W") : 30;
	apps::RunOptions run;
	estimators::SlidingWindowOptions o = run.window;
	o.window_size = W;
	if (argc > 3) o.relinearized_poses = count_arg(argv[3], "relinearized poses");
	if (argc > 4) o.sensor.std_range = non_negative_arg(argv[4], "sensor std range");
	if (argc > 5) o.sensor.std_yaw = non_negative_arg(argv[5], "sensor std yaw") * M_PI / 180;
	if (argc > 6) throw std::invalid_argument("too many arguments (see --help)");
	o.validate();
	const io::Rawlog rawlog = io::read_rawlog(path);
	const auto gt = eval::read_ground_truth_for(eval::default_ground_truth_path(path), rawlog.steps.size());

	estimators::SlidingWindowEstimator window(o);
	for (const auto& step : rawlog.steps) window.process(step);
	window.finish();
	const PoseByStamp online = by_stamp(window.online_trajectory()), lagged = by_stamp(window.lagged_trajectory());
	const PoseByStamp batch = by_stamp(better_batch(rawlog, o, run.batch_max_iterations, window.lagged_trajectory()));
	const auto [causal, lag_w] = lag_optima(rawlog, o, static_cast<std::size_t>(W));

	const double b0 = rmse_at(gt, causal, batch), bw = rmse_at(gt, lag_w, batch);
	const double c = rmse_at(gt, causal, by_stamp(causal)), l = rmse_at(gt, lag_w, by_stamp(lag_w));
	const double wo = rmse_at(gt, causal, online), wl = rmse_at(gt, lag_w, lagged);
	std::printf("%s, W = %d, %d re-linearised poses (APE translation rmse, m, not aligned)\n", path.c_str(), W,
				o.relinearized_poses);
	std::printf("lag 0 (%zu steps): causal optimum %.4f, window online %.4f, batch %.4f; online / causal %.2f, "
				"causal / batch %.2f\n",
				causal.size(), c, wo, b0, wo / c, c / b0);
	std::printf("lag W (%zu steps): lag optimum %.4f, window lagged %.4f, batch %.4f; lagged / lag optimum %.2f, "
				"lag optimum / batch %.2f, window lagged / batch %.2f\n",
				lag_w.size(), l, wl, bw, wl / l, l / bw, wl / bw);
	return 0;
}
catch (const std::exception& e)
{
	std::fprintf(stderr, "swba_window_lag_bound: %s\n", e.what());
	return 1;
}
