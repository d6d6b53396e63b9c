// swba monoba: monocular inverse-depth BA on a synthetic arc scene, gauge modes and the prior-weight
// sweep (logic in swba/apps/monoba.h; see doc/monoba.md).
#include <swba/apps/monoba.h>

#include <iostream>
#include <limits>
#include <stdexcept>
#include <string>

#include "cli.h"
#include "command.h"

namespace
{
struct MonobaCommandLine
{
	TCLAP::CmdLine cmd{
		"Monocular bundle adjustment on a synthetic scene: N cameras on an arc, M points "
		"as inverse depths in their first observing camera, observations on the normalised image plane. "
		"Gauge: free, fixed (first K poses constant) or prior (pose prior W*I on the first K poses). "
		"--sweep-prior-weights runs W over 0, 1, 10, ..., 1e10 plus free and fixed reference rows. "
		"See doc/monoba.md.",
		' ', "0.1.0"};
	TCLAP::ValueArg<int> cameras{"", "cameras", "number of cameras N >= 2 (Default: 3)", false, 3, "N", cmd};
	TCLAP::ValueArg<int> points{"", "points", "number of points M >= 1 (Default: 20)", false, 20, "M", cmd};
	TCLAP::ValueArg<double> noise{"", "noise",
								  "observation noise sigma on the normalised image plane (Default: 1/460 = "
								  "0.00217391, one pixel at f = 460 px)",
								  false, 1.0 / 460.0, "S", cmd};
	TCLAP::ValueArg<double> depth_noise{
		"", "depth-noise", "sigma of the initial depth perturbation, m (Default: 1)", false, 1.0, "S", cmd};
	TCLAP::ValueArg<double> pose_noise_m{
		"", "pose-noise-m", "initial translation noise sigma of cameras >= K, m (Default: 0)", false, 0.0, "S", cmd};
	TCLAP::ValueArg<double> pose_noise_rad{
		"", "pose-noise-rad", "initial rotation noise sigma of cameras >= K, rad (Default: 0)", false, 0.0, "S", cmd};
	TCLAP::ValueArg<long long> seed{"", "seed", "RNG seed (Default: 0)", false, 0, "K", cmd};
	TCLAP::ValueArg<std::string> gauge{
		"", "gauge", "gauge handling: free, fixed or prior (Default: fixed)", false, "fixed", "free|fixed|prior", cmd};
	TCLAP::ValueArg<int> fix{"", "fix",
							 "K: number of leading poses held constant (fixed) or under the prior (prior, sweep); "
							 "1 <= K <= N (Default: 2: removes the 7-DoF gauge incl. scale)",
							 false, 2, "K", cmd};
	TCLAP::ValueArg<double> prior_weight{
		"", "prior-weight", "W >= 0: prior information W*I on each of the first K poses (Default: 1e4)", false, 1e4,
		"W", cmd};
	TCLAP::SwitchArg sweep{"", "sweep-prior-weights",
						   "run the prior-weight sweep (W = 0, 1, 10, ..., 1e10, plus free and fixed rows) and print "
						   "the table",
						   cmd};
	TCLAP::ValueArg<int> seeds{"", "seeds", "sweep: average over seeds K..K+S-1 (Default: 1)", false, 1, "S", cmd};
	TCLAP::ValueArg<int> repetitions{
		"", "repetitions", "solves per run for the median time (Default: 1)", false, 1, "R", cmd};
	TCLAP::ValueArg<int> max_iterations = swba::app::max_iterations_arg(cmd, 50);
	TCLAP::ValueArg<int> threads = swba::app::threads_arg(cmd);
	TCLAP::ValueArg<std::string> out{
		"", "out", "also write the report / sweep table to this file (Default: not written)", false, "", "FILE", cmd};
	TCLAP::SwitchArg progress{"", "progress", "print the per-iteration LM table", cmd};
};

void set_scene(MonobaCommandLine& a, swba::problems::MonoBASceneOptions& so)
{
	so.cameras = a.cameras.getValue();
	so.points = a.points.getValue();
	so.noise = a.noise.getValue();
	so.depth_noise_m = a.depth_noise.getValue();
	so.pose_noise_m = a.pose_noise_m.getValue();
	so.pose_noise_rad = a.pose_noise_rad.getValue();
	if (a.seed.getValue() < 0 || a.seed.getValue() > std::numeric_limits<unsigned>::max())
		throw std::invalid_argument("--seed must be in [0, " + std::to_string(std::numeric_limits<unsigned>::max()) +
									"]");
	so.seed = static_cast<unsigned>(a.seed.getValue());
	so.pose_noise_from = 0;  // set from --fix once the number of cameras is known to be valid
	so.validate();
	if (a.fix.getValue() < 1 || a.fix.getValue() > so.cameras)
		throw std::invalid_argument("--fix " + std::to_string(a.fix.getValue()) + " is out of range [1, " +
									std::to_string(so.cameras) + "] (number of cameras)");
	so.pose_noise_from = a.fix.getValue();
}

/** Gauge, anchors and weight, with the flag combinations that make no sense rejected (--fix is in range:
 * set_scene checked it). */
void set_adjustment(MonobaCommandLine& a, swba::apps::MonoBAOptions& mo)
{
	using swba::GaugeMode;
	const bool sweep = a.sweep.getValue();
	mo.gauge = swba::parse_gauge_mode(a.gauge.getValue());
	if (sweep && (a.gauge.isSet() || a.prior_weight.isSet()))
		throw std::invalid_argument("--sweep-prior-weights runs every gauge and weight: do not give --gauge or "
									"--prior-weight");
	if (!sweep && mo.gauge == GaugeMode::Free && a.fix.isSet())
		throw std::invalid_argument("--fix has no effect with --gauge free");
	if (!sweep && mo.gauge != GaugeMode::Prior && a.prior_weight.isSet())
		throw std::invalid_argument("--prior-weight needs --gauge prior");
	mo.anchors = a.fix.getValue();
	mo.prior_weight = a.prior_weight.getValue();
	mo.solver.max_iterations = a.max_iterations.getValue();
	mo.solver.num_threads = a.threads.getValue();
	if (mo.solver.max_iterations < 0) throw std::invalid_argument("--max-iterations must be >= 0");
	if (mo.solver.num_threads < 1) throw std::invalid_argument("--threads must be >= 1");
	mo.solver.progress_to_stdout = a.progress.getValue() && !sweep;
	mo.validate();
}

/** The typed options; invalid values and flag combinations are usage errors. */
swba::apps::MonoBAAppOptions options_from(MonobaCommandLine& a)
{
	swba::apps::MonoBAAppOptions o;
	try
	{
		set_scene(a, o.scene);
		set_adjustment(a, o.adjustment);
		o.sweep = a.sweep.getValue();
		o.sweep_seeds = a.seeds.getValue();
		o.repetitions = a.repetitions.getValue();
		o.sweep_options().validate();
		if (a.seeds.isSet() && !o.sweep) throw std::invalid_argument("--seeds needs --sweep-prior-weights");
	}
	catch (const std::invalid_argument& e)
	{
		throw swba::app::UsageError(e.what());
	}
	o.out_path = a.out.getValue();
	return o;
}

SWBA_REGISTER_COMMAND("monoba", "monocular inverse-depth BA demo and gauge study (synthetic)",
					  swba::app::app_command<MonobaCommandLine>(swba::apps::run_monoba_app));
}  // namespace
