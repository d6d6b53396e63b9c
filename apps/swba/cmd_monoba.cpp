// swba monoba: monocular inverse-depth BA on a synthetic arc scene, gauge modes and the prior-weight
// sweep (logic in swba/estimators/monoba.h; see doc/monoba.md).
#include <swba/estimators/monoba.h>

#include <fstream>
#include <iostream>
#include <limits>

#include "cli.h"
#include "command.h"

namespace
{
int run_monoba_cmd(int argc, char** argv)
{
	namespace est = swba::estimators;
	TCLAP::CmdLine cmd(
		"Monocular bundle adjustment on a synthetic scene (seed 000's TestMonoBA): N cameras on an arc, M points "
		"as inverse depths in their first observing camera, observations on the normalised image plane. "
		"Gauge: free, fixed (first K poses constant) or prior (pose prior W*I on the first K poses). "
		"--sweep-prior-weights runs W over 0, 1, 10, ..., 1e10 plus free and fixed reference rows. "
		"See doc/monoba.md.",
		' ', "0.1.0");
	TCLAP::ValueArg<int> cameras("", "cameras", "number of cameras N >= 2 (default 3)", false, 3, "N", cmd);
	TCLAP::ValueArg<int> points("", "points", "number of points M >= 1 (default 20)", false, 20, "M", cmd);
	TCLAP::ValueArg<double> noise("", "noise",
								  "observation noise sigma on the normalised image plane (default 1/460 = "
								  "0.00217391, one pixel at f = 460 px)",
								  false, 1.0 / 460.0, "S", cmd);
	TCLAP::ValueArg<double> depth_noise("", "depth-noise", "sigma of the initial depth perturbation, m (default 1)",
										false, 1.0, "S", cmd);
	TCLAP::ValueArg<double> pose_noise_m("", "pose-noise-m",
										 "initial translation noise sigma of cameras >= K, m (default 0)", false, 0.0,
										 "S", cmd);
	TCLAP::ValueArg<double> pose_noise_rad("", "pose-noise-rad",
										   "initial rotation noise sigma of cameras >= K, rad (default 0)", false, 0.0,
										   "S", cmd);
	TCLAP::ValueArg<long long> seed("", "seed", "RNG seed (default 0)", false, 0, "K", cmd);
	TCLAP::ValueArg<std::string> gauge("", "gauge", "gauge handling: free, fixed or prior (default fixed)", false,
									   "fixed", "free|fixed|prior", cmd);
	TCLAP::ValueArg<int> fix("", "fix",
							 "K: number of leading poses held constant (fixed) or under the prior (prior, sweep); "
							 "1 <= K <= N (default 2: removes the 7-DoF gauge incl. scale)",
							 false, 2, "K", cmd);
	TCLAP::ValueArg<double> prior_weight("", "prior-weight",
										 "W >= 0: prior information W*I on each of the first K poses (default 1e4)",
										 false, 1e4, "W", cmd);
	TCLAP::SwitchArg sweep("", "sweep-prior-weights",
						   "run the prior-weight sweep (W = 0, 1, 10, ..., 1e10, plus free and fixed rows) and print "
						   "the table",
						   cmd);
	TCLAP::ValueArg<int> seeds("", "seeds", "sweep: average over seeds K..K+S-1 (default 1)", false, 1, "S", cmd);
	TCLAP::ValueArg<int> repetitions("", "repetitions", "solves per run for the median time (default 1)", false, 1,
									 "R", cmd);
	TCLAP::ValueArg<std::string> out("", "out", "also write the report / sweep table to this file", false, "",
									 "FILE", cmd);
	TCLAP::ValueArg<int> max_iterations("", "max-iterations", "maximum LM iterations (default 50)", false, 50, "K",
										cmd);
	TCLAP::ValueArg<int> threads("", "threads", "threads for evaluation and assembly (default 1)", false, 1, "N",
								 cmd);
	TCLAP::SwitchArg progress("", "progress", "print the per-iteration LM table", cmd);
	if (auto rc = swba::app::parse_command_line(cmd, argc, argv)) return *rc;

	using swba::app::UsageError;
	est::MonoBASceneOptions so;
	est::MonoBAOptions mo;
	est::SweepOptions sw;
	try
	{
		so.cameras = cameras.getValue();
		so.points = points.getValue();
		so.noise = noise.getValue();
		so.depth_noise_m = depth_noise.getValue();
		so.pose_noise_m = pose_noise_m.getValue();
		so.pose_noise_rad = pose_noise_rad.getValue();
		if (seed.getValue() < 0 || seed.getValue() > std::numeric_limits<unsigned>::max())
			throw std::invalid_argument("--seed must be in [0, " + std::to_string(std::numeric_limits<unsigned>::max()) +
										"]");
		so.seed = static_cast<unsigned>(seed.getValue());
		so.pose_noise_from = fix.getValue();
		if (std::string why; !so.is_valid(&why)) throw std::invalid_argument(why);

		mo.gauge = swba::parse_gauge_mode(gauge.getValue());
		if (sweep.getValue() && (gauge.isSet() || prior_weight.isSet()))
			throw std::invalid_argument("--sweep-prior-weights runs every gauge and weight: do not give --gauge or "
										"--prior-weight");
		if (!sweep.getValue() && mo.gauge == swba::GaugeMode::Free && fix.isSet())
			throw std::invalid_argument("--fix has no effect with --gauge free");
		if (!sweep.getValue() && mo.gauge != swba::GaugeMode::Prior && prior_weight.isSet())
			throw std::invalid_argument("--prior-weight needs --gauge prior");
		if (fix.getValue() < 1 || fix.getValue() > so.cameras)
			throw std::invalid_argument("--fix " + std::to_string(fix.getValue()) + " is out of range [1, " +
										std::to_string(so.cameras) + "] (number of cameras)");
		mo.anchors = fix.getValue();
		mo.prior_weight = prior_weight.getValue();
		mo.solver.max_iterations = max_iterations.getValue();
		mo.solver.num_threads = threads.getValue();
		mo.solver.progress_to_stdout = progress.getValue() && !sweep.getValue();
		if (std::string why; !mo.is_valid(&why)) throw std::invalid_argument(why);
		sw.seeds = seeds.getValue();
		sw.repetitions = repetitions.getValue();
		if (std::string why; !sw.is_valid(&why)) throw std::invalid_argument(why);
		if (seeds.isSet() && !sweep.getValue()) throw std::invalid_argument("--seeds needs --sweep-prior-weights");
	}
	catch (const std::invalid_argument& e)
	{
		throw UsageError(e.what());
	}

	std::string text;
	if (sweep.getValue())
		text = est::format_sweep_table(est::run_prior_weight_sweep(so, mo, sw), so, mo, sw);
	else
	{
		const est::MonoBAScene scene = est::make_monoba_scene(so);
		const est::MonoBAResult result = est::run_monoba(scene, mo, sw.repetitions);
		text = est::format_monoba_report(scene, mo, result);
		if (!result.summary.is_solution_usable())
		{
			std::cout << text;
			throw std::runtime_error("optimisation failed: " + result.summary.message);
		}
	}
	std::cout << text;
	if (!out.getValue().empty())
	{
		std::ofstream f(out.getValue());
		if (!(f << text) || !f.flush()) throw std::runtime_error("cannot write " + out.getValue());
		std::cout << "Wrote " << out.getValue() << "\n";
	}
	return 0;
}
SWBA_REGISTER_COMMAND("monoba", "monocular inverse-depth BA demo and gauge study (synthetic)", run_monoba_cmd);
}  // namespace
