// swba jobs: a sweep of swba run as a job list for GNU parallel or a Slurm job array; swba merge
// combines the jobs' outputs (doc/sweeps.md). Logic in swba/apps/sweep.h.
#include <swba/apps/sweep.h>

#include <filesystem>
#include <iostream>

#include "cli.h"
#include "command.h"

namespace swba::app
{
std::string this_executable()
{
	std::error_code ec;
	const auto p = std::filesystem::read_symlink("/proc/self/exe", ec);
	return ec ? std::string("swba") : p.string();
}

namespace
{
int run_jobs(int argc, char** argv)
{
	TCLAP::CmdLine cmd(
		"Writes a sweep of swba run as independent jobs: one shell command per line of DIR/jobs.txt, one job per "
		"rawlog (or simulated rawlog, one per seed) and window size W; the widest W of each rawlog also runs the EKF "
		"and the batch. Run them with GNU parallel (parallel -j 2 --joblog DIR/joblog --bar < DIR/jobs.txt; "
		"--sshlogin for other machines) or as a Slurm job array (sbatch DIR/jobs.sbatch), then swba merge DIR "
		"writes the tables and plots one swba run writes, with the same figures. Options of the runs: --config.",
		' ', "0.1.0");
	TCLAP::UnlabeledMultiArg<std::string> rawlogs("RAWLOG", "rawlogs to run on (ground truth next to each, as swba run "
															"finds it)",
												  false, "RAWLOG", cmd);
	TCLAP::ValueArg<std::string> simulate("", "simulate",
										  "simulated rawlogs instead: simul-landmarks INI, one rawlog per seed, made by "
										  "each job (swba simulate)",
										  false, "", "INI", cmd);
	TCLAP::ValueArg<std::string> seeds("", "seeds", "seeds of --simulate, e.g. 1-10 or 1,4,7", false, "", "LIST", cmd);
	OverrideArg<std::string> windows("windows", "LIST", "the config's [window] sizes, 5,10,20,30",
									 "window sizes W, comma-separated, each >= 2: one job each", cmd);
	TCLAP::ValueArg<std::string> config("", "config", "swba run INI for every job (see swba run --help)", false, "",
										"INI", cmd);
	TCLAP::ValueArg<std::string> out("", "out", "sweep directory, created (Default: swba_sweep)", false, "swba_sweep",
									 "DIR", cmd);
	OverrideArg<std::string> swba("swba", "PATH", "this swba, " + this_executable(),
								  "swba executable the job lines call; with parallel --sshlogin it must exist on every "
								  "machine",
								  cmd);
	if (auto rc = parse_command_line(cmd, argc, argv)) return *rc;
	apps::SweepOptions o;
	if (config.isSet()) apps::load_run_config(config.getValue(), o.run);  // a bad file: exit 1
	try
	{
		if (windows.isSet()) o.run.windows = apps::parse_window_list(windows.getValue(), "--windows");
		if (seeds.isSet()) o.seeds = apps::parse_seed_list(seeds.getValue());
		o.rawlogs = rawlogs.getValue();
		o.simulate_ini = simulate.getValue();
		o.dir = out.getValue();
		o.swba = swba.isSet() ? swba.getValue() : this_executable();
		o.validate();
	}
	catch (const std::invalid_argument& e)
	{
		throw UsageError(e.what());
	}
	const apps::SweepPlan plan = apps::plan_sweep(o);
	apps::write_sweep(o, plan, std::cerr);
	std::cout << plan.dir << "/jobs.txt\n";
	return 0;
}
SWBA_REGISTER_COMMAND("jobs", "a sweep of swba run as a job list for GNU parallel or Slurm", run_jobs);

int run_merge(int argc, char** argv)
{
	TCLAP::CmdLine cmd(
		"Merges the jobs of a sweep (swba jobs, swba nees --jobs-only) once they have all run. A run sweep: per "
		"rawlog the files one swba run writes (TUM and covariance files, ape.txt, ape.csv, summary.json, "
		"config.ini, plots) with the same figures, the comparison table on stdout and, for several rawlogs, the "
		"APE rmse of each estimator over them. A NEES sweep: the average NEES table, nees.csv and plots "
		"(swba nees --help). A job that has not run or failed is named, with how to re-run it.",
		' ', "0.1.0");
	TCLAP::UnlabeledValueArg<std::string> dir("DIR", "sweep directory", true, "", "DIR", cmd);
	TCLAP::ValueArg<std::string> out("", "out", "output directory, created (Default: DIR/merged, DIR/nees for a NEES sweep)",
									 false, "", "DIR");
	TCLAP::SwitchArg no_plots("", "no-plots", "do not write gnuplot plots");
	cmd.add(out);
	cmd.add(no_plots);
	if (auto rc = parse_command_line(cmd, argc, argv)) return *rc;
	apps::MergeOptions o;
	o.dir = dir.getValue();
	o.out_dir = out.getValue();
	o.plots = !no_plots.getValue();
	return apps::merge_sweep(o, std::cout, std::cerr);
}
SWBA_REGISTER_COMMAND("merge", "merge the jobs of a sweep into swba run's tables (or NEES)", run_merge);
}  // namespace
}  // namespace swba::app
