// swba simulate: one simulated rawlog from a simul-landmarks INI and a seed (doc/sweeps.md). Logic in
// swba/apps/simulate.h.
#include <swba/apps/simulate.h>

#include <iostream>

#include "cli.h"
#include "command.h"

namespace swba::app
{
namespace
{
int run_simulate(int argc, char** argv)
{
	TCLAP::CmdLine cmd(
		"Makes one simulated rawlog with MRPT's simul-landmarks (Debian package mrpt-apps) from INI with the given "
		"random seed: writes DIR/NAME.rawlog, DIR/NAME_ground_truth_robot_path.txt (what swba run reads as ground "
		"truth), DIR/NAME_ground_truth.txt (landmarks), the INI it ran with and its log. The INI's [Params] "
		"random_seed, outFile and outDir are replaced; everything else is the INI's.",
		' ', "0.1.0");
	TCLAP::UnlabeledValueArg<std::string> ini("INI", "simul-landmarks INI (e.g. " + share_dir() +
														 "/rawlogs/kf-slam_6D_noisy.ini)",
											  true, "", "INI", cmd);
	TCLAP::ValueArg<std::string> name("", "name", "base name of the outputs (Default: <INI stem>_seed<S>)", false, "",
									  "NAME");
	TCLAP::ValueArg<std::string> out("", "out", "output directory, created (Default: .)", false, ".", "DIR");
	TCLAP::ValueArg<long> seed("", "seed", "random seed of the simulation, >= 1 (Default: 1)", false, 1, "S");
	TCLAP::SwitchArg keep("", "keep-declared-noise",
						  "keep simul-landmarks' rawlog as written: by default the odometry of its motionless first steps, "
						  "which it writes without noise, is declared exact instead of with the moving steps' covariance "
						  "(doc/sweeps.md)");
	for (TCLAP::Arg* a : std::initializer_list<TCLAP::Arg*>{&seed, &out, &name, &keep}) cmd.add(*a);
	if (auto rc = parse_command_line(cmd, argc, argv)) return *rc;
	apps::SimulateOptions o;
	o.ini = ini.getValue();
	o.seed = seed.getValue();
	o.out_dir = out.getValue();
	o.name = name.getValue();
	o.keep_declared_noise = keep.getValue();
	validate_usage(o);
	const apps::SimulatedRawlog r = apps::simulate_rawlog(o, std::cerr);
	std::cout << r.rawlog << "\n";
	return 0;
}
SWBA_REGISTER_COMMAND("simulate", "a simulated rawlog from a simul-landmarks INI and a seed", run_simulate);
}  // namespace
}  // namespace swba::app
