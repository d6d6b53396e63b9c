// swba nees: the NEES sweep written, run job after job, merged; swba merge's dispatch (see nees.h).
#include <swba/apps/nees.h>
#include <swba/apps/sweep.h>
#include <swba/core/timing.h>

#include <cstdlib>
#include <filesystem>
#include <ostream>
#include <stdexcept>
#include <sys/wait.h>

namespace swba::apps
{
namespace fs = std::filesystem;

RunOptions NeesOptions::default_run_options()
{
	RunOptions o;
	o.windows = {10};
	o.fej = {true, false};
	o.ekf_methods = {"kfEKFAlaDavison"};
	o.run_batch = false;
	o.plots = false;
	o.progress = false;
	return o;
}

void NeesOptions::validate() const
{
	if (runs < 1) throw std::invalid_argument("--runs must be >= 1");
	if (first_seed < 1) throw std::invalid_argument("--first-seed must be >= 1");
	if (ini.empty()) throw std::invalid_argument("no simul-landmarks INI given (--ini)");
	sweep_options().validate();
}

SweepOptions NeesOptions::sweep_options() const
{
	SweepOptions s;
	s.kind = SweepKind::Nees;
	s.simulate_ini = ini;
	for (int i = 0; i < runs; i++) s.seeds.push_back(first_seed + i);
	s.run = run;
	s.dir = dir;
	s.swba = swba;
	return s;
}

namespace
{
/** Runs `command` with /bin/sh, stdout and stderr into `log_file`; returns a description of the
 * failure, or "" when it exited 0. */
std::string run_shell(const std::string& command, const std::string& log_file)
{
	const std::string line = "( " + command + " ) > " + shell_quote(log_file) + " 2>&1";
	const int status = std::system(line.c_str());
	if (status == -1) return "could not start /bin/sh";
	if (WIFSIGNALED(status)) return "killed by signal " + std::to_string(WTERMSIG(status));
	if (WIFEXITED(status) && WEXITSTATUS(status) != 0) return "exit code " + std::to_string(WEXITSTATUS(status));
	return "";
}
}  // namespace

int run_nees_app(const NeesOptions& o, std::ostream& out, std::ostream& log)
{
	o.validate();
	const SweepOptions so = o.sweep_options();
	const SweepPlan plan = plan_sweep(so);
	write_sweep(so, plan, log, o.jobs_only, "swba nees");
	if (o.jobs_only) return 0;
	log << "swba nees: running the " << plan.jobs.size() << " jobs of " << plan.dir
		<< "/jobs.txt here, one after the other (--jobs-only writes them for GNU parallel or Slurm instead)\n";
	for (const auto& job : plan.jobs)
	{
		const std::string dir = job_directory(plan, job);
		std::error_code ec;
		fs::create_directories(dir, ec);
		if (ec) throw std::runtime_error("cannot create '" + dir + "': " + ec.message());
		const auto t0 = SteadyClock::now();
		const std::string failure = run_shell(job.command, dir + "/job.log");
		if (!failure.empty())
			throw std::runtime_error("job " + std::to_string(job.id) + " of " + std::to_string(plan.jobs.size()) +
									 " (seed " + std::to_string(plan.groups[job.group].seed) + ") failed, " + failure +
									 ": see " + dir + "/job.log; re-run it alone: sed -n " + std::to_string(job.id) +
									 "p " + plan.dir + "/jobs.txt | bash, then swba merge " + plan.dir);
		const double s = seconds_since(t0);
		char buf[64];
		std::snprintf(buf, sizeof(buf), "%.1f", s);
		log << "swba nees: job " << job.id << "/" << plan.jobs.size() << " (seed " << plan.groups[job.group].seed
			<< ") done in " << buf << " s\n"
			<< std::flush;
	}
	MergeOptions mo;
	mo.dir = plan.dir;
	mo.plots = o.plots;
	mo.program = "swba nees";
	merge_nees_sweep(plan, mo, out, log);
	return 0;
}

int merge_sweep(const MergeOptions& options, std::ostream& out, std::ostream& log)
{
	const SweepPlan plan = read_sweep_manifest(options.dir);
	if (plan.kind == SweepKind::Nees)
		merge_nees_sweep(plan, options, out, log);
	else
		merge_run_sweep(plan, options, out, log);
	return 0;
}
}  // namespace swba::apps
