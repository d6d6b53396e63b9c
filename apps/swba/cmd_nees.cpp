// swba nees: average NEES of the estimators over N simulated runs against the 95% chi-square band
// (doc/sweeps.md). Logic in swba/apps/nees.h.
#include <swba/apps/nees.h>

#include <iostream>

#include "cli.h"
#include "command.h"

namespace swba::app
{
namespace
{
const char* const kAbout =
		"Filter consistency by Monte Carlo: makes N simulated rawlogs with simul-landmarks (seeds S, S+1, ...), runs "
		"swba run on each (the window online and lagged at each W, FEJ on and off, MRPT's EKF), and prints per "
		"estimator the average over the runs of the position NEES (3 dof) and pose NEES (6 dof) at each step against "
		"the 95% chi-square band of that average: the share of steps inside it and the mean. No alignment: the "
		"estimate and the ground truth share the first pose. Needs the covariance files swba run writes next to its "
		"TUM files. The runs are the jobs of a sweep in DIR: --jobs-only writes them for GNU parallel or Slurm, then "
		"swba merge DIR prints the same table. Writes DIR/nees/nees.txt, nees.csv and plots.";

/** The command line of `swba nees`: every option, and how it fills NeesOptions. */
struct NeesCommandLine
{
	TCLAP::CmdLine cmd{kAbout, ' ', "0.1.0"};
	// In the order --help lists them (cli.cpp), each added to `cmd` where it is declared.
	TCLAP::ValueArg<int> runs{"", "runs", "number of simulated runs N, >= 1 (Default: 50)", false, 50, "N", cmd};
	TCLAP::ValueArg<long> first_seed{"", "first-seed", "seed of the first run, >= 1 (Default: 1)", false, 1, "S", cmd};
	OverrideArg<std::string> ini{"ini", "INI", share_dir() + "/rawlogs/kf-slam_6D_noisy.ini, 600 steps, 6D",
								 "simul-landmarks INI", cmd};
	TCLAP::ValueArg<std::string> config{
		"", "config", "swba run INI for every run (see swba run --help); the options below override it", false, "",
		"INI", cmd};
	OverrideArg<std::string> windows{"windows", "LIST", "10", "window sizes W, comma-separated, each >= 2", cmd};
	OverrideArg<std::string> fej{"fej", "on|off|both", "both", "first-estimate Jacobians: on, off or both", cmd};
	OverrideArg<std::string> ekf_method{"ekf-method", "NAME,...", "kfEKFAlaDavison", "MRPT EKF methods, comma-separated",
										cmd};
	TCLAP::SwitchArg no_ekf{"", "no-ekf", "do not run MRPT's EKF", cmd};
	TCLAP::SwitchArg batch{"", "batch", "also the batch solution (its covariance: the full smoothing marginals)", cmd};
	OverrideArg<int> max_steps{"max-steps", "N", "0", "process at most N steps of each rawlog (0 = all)", cmd};
	TCLAP::ValueArg<std::string> out{"", "out", "sweep directory, created (Default: swba_nees)", false, "swba_nees",
									 "DIR", cmd};
	TCLAP::SwitchArg jobs_only{"", "jobs-only", "only write DIR/jobs.txt and DIR/jobs.sbatch; run them, then swba merge DIR",
							   cmd};
	OverrideArg<std::string> swba{"swba", "PATH", "this swba, " + this_executable(), "swba executable the job lines call",
								  cmd};
	TCLAP::SwitchArg no_plots{"", "no-plots", "do not write gnuplot plots", cmd};

	/** Fills `o` from the command line (its run options already loaded from --config); throws
	 * std::invalid_argument naming the option. */
	void apply(apps::NeesOptions& o)
	{
		o.run.plots = o.run.progress = false;
		if (windows.isSet()) o.run.windows = apps::parse_window_list(windows.getValue(), "--windows");
		if (fej.isSet()) o.run.fej = apps::parse_fej_list(fej.getValue());
		if (ekf_method.isSet()) o.run.ekf_methods = apps::parse_ekf_method_list(ekf_method.getValue());
		if (no_ekf.isSet()) o.run.run_ekf = false;
		if (batch.isSet()) o.run.run_batch = true;
		if (max_steps.isSet())
		{
			if (max_steps.getValue() < 0) throw std::invalid_argument("--max-steps must be >= 0");
			o.run.max_steps = static_cast<std::size_t>(max_steps.getValue());
		}
		o.runs = runs.getValue();
		o.first_seed = first_seed.getValue();
		o.ini = ini.isSet() ? ini.getValue() : share_dir() + "/rawlogs/kf-slam_6D_noisy.ini";
		o.dir = out.getValue();
		o.swba = swba.isSet() ? swba.getValue() : this_executable();
		o.jobs_only = jobs_only.getValue();
		o.plots = !no_plots.getValue();
	}
};

int run_nees(int argc, char** argv)
{
	NeesCommandLine c;
	if (auto rc = parse_command_line(c.cmd, argc, argv)) return *rc;
	apps::NeesOptions o;
	if (c.config.isSet()) apps::load_run_config(c.config.getValue(), o.run);  // a bad file: exit 1
	try
	{
		c.apply(o);
		o.validate();
	}
	catch (const std::invalid_argument& e)
	{
		throw UsageError(e.what());
	}
	return apps::run_nees_app(o, std::cout, std::cerr);
}
SWBA_REGISTER_COMMAND("nees", "average NEES over simulated runs vs the 95% chi-square band", run_nees);
}  // namespace
}  // namespace swba::app
