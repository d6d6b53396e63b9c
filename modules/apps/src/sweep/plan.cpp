// swba jobs: the job list of a sweep, its Slurm script and its manifest (see sweep.h).
#include <swba/apps/inertial_run.h>
#include <swba/apps/simulate.h>
#include <swba/apps/sweep.h>
#include <swba/core/file.h>
#include <swba/eval/ground_truth.h>
#include <swba/io/observation_rawlog.h>
#include <swba/io/rawlog.h>

#include "../json_values.h"
#include "summary_json.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <map>
#include <ostream>
#include <set>
#include <sstream>
#include <stdexcept>

namespace swba::apps
{
namespace fs = std::filesystem;

namespace
{
constexpr const char* kRunConfig = "config.ini";
constexpr const char* kWindowsConfig = "config_windows.ini";

/** A file-safe name: letters, digits, '-', '_', '.'; anything else becomes '_'. */
std::string file_safe(std::string s)
{
	for (auto& c : s)
		if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.')) c = '_';
	return s;
}

std::string rawlog_stem(const std::string& path)
{
	std::string name = fs::path(path).filename().string();
	for (const std::string ext : {".rawlog.gz", ".rawlog"})
		if (name.size() > ext.size() && name.compare(name.size() - ext.size(), ext.size(), ext) == 0)
			return name.substr(0, name.size() - ext.size());
	return name;
}

std::string absolute(const std::string& p) { return fs::absolute(p).lexically_normal().string(); }

/** The run options every job loads: per-job fields cleared (the command line sets them), no plots
 * (the merge draws them) and no progress lines. */
RunOptions job_run_options(const RunOptions& run, bool first_job_of_rawlog)
{
	RunOptions o = run;
	o.rawlog.clear();
	o.ground_truth.clear();
	o.out_dir = RunOptions{}.out_dir;
	o.plots = false;
	o.progress = false;
	if (!first_job_of_rawlog) o.run_ekf = o.run_batch = o.run_causal = false;
	return o;
}

std::string run_command(const SweepPlan& plan, const std::string& swba, const SweepGroup& g, const SweepJob& job,
						bool first)
{
	const std::string out = job_directory(plan, job);
	std::string cmd;
	std::string rawlog = g.rawlog;
	if (!plan.simulate_ini.empty())
	{
		// One directory per rawlog, shared by its jobs: each job simulates (so it can run alone), and
		// simulate_rawlog replaces the files atomically with the same data, so a job reading them is
		// never disturbed, and every job of the rawlog names the same files (the merge checks that).
		const std::string sim_dir = plan.dir + "/jobs/" + g.name + "/rawlog";
		cmd = shell_quote(swba) + " simulate " + shell_quote(plan.simulate_ini) + " --seed " + std::to_string(g.seed) +
			  " --name " + shell_quote(g.name) + " --out " + shell_quote(sim_dir) + " && ";
		rawlog = sim_dir + "/" + g.name + ".rawlog";
	}
	cmd += shell_quote(swba) + " run " + shell_quote(rawlog);
	if (!g.ground_truth.empty()) cmd += " --gt " + shell_quote(g.ground_truth);
	cmd += " --config " + shell_quote(plan.dir + "/" + (first ? kRunConfig : kWindowsConfig));
	if (job.window) cmd += " --windows " + std::to_string(job.window);
	cmd += " --out " + shell_quote(out);
	return cmd;
}
}  // namespace

void SweepOptions::validate() const
{
	run.validate();
	if (dir.empty()) throw std::invalid_argument("--out must not be empty");
	if (swba.empty()) throw std::invalid_argument("--swba must not be empty");
	if (rawlogs.empty() && simulate_ini.empty()) throw std::invalid_argument("no rawlog given (RAWLOG... or --simulate INI)");
	if (!rawlogs.empty() && !simulate_ini.empty())
		throw std::invalid_argument("give rawlogs or --simulate, not both (two sweeps)");
	if (!simulate_ini.empty() && seeds.empty()) throw std::invalid_argument("--simulate needs --seeds");
	if (simulate_ini.empty() && !seeds.empty()) throw std::invalid_argument("--seeds needs --simulate INI");
	if (kind == SweepKind::Nees && simulate_ini.empty())
		throw std::invalid_argument("a NEES sweep runs on simulated rawlogs (--simulate INI --seeds ...)");
	std::set<long> distinct;
	for (long s : seeds)
	{
		if (s < 1) throw std::invalid_argument("--seeds: each seed must be >= 1, got " + std::to_string(s));
		if (!distinct.insert(s).second) throw std::invalid_argument("--seeds: seed " + std::to_string(s) + " given twice");
	}
	for (const char c : dir)
		if (std::isspace(static_cast<unsigned char>(c)))
			throw std::invalid_argument("--out must not contain white space (Slurm's #SBATCH lines cannot quote it)");
}

std::vector<long> parse_seed_list(const std::string& text, const std::string& what)
{
	auto integer = [&](const std::string& item) {
		try
		{
			const long long v = ini::parse_integer(item);
			if (v < 1 || v > 1000000000) throw std::invalid_argument("");
			return static_cast<long>(v);
		}
		catch (const std::exception&)
		{
			throw std::invalid_argument(what + ": '" + item + "' is not a seed (an integer >= 1)");
		}
	};
	std::vector<long> seeds;
	for (const auto& item : split_list(text, what))
	{
		const auto dash = item.find('-', 1);
		const long a = integer(dash == std::string::npos ? item : item.substr(0, dash));
		const long b = dash == std::string::npos ? a : integer(item.substr(dash + 1));
		if (b < a) throw std::invalid_argument(what + ": range '" + item + "' is reversed");
		if (b - a >= 100000) throw std::invalid_argument(what + ": range '" + item + "' is too long");
		for (long s = a; s <= b; s++)
		{
			if (std::find(seeds.begin(), seeds.end(), s) != seeds.end())
				throw std::invalid_argument(what + ": seed " + std::to_string(s) + " given twice");
			seeds.push_back(s);
		}
	}
	return seeds;
}

std::string shell_quote(const std::string& w)
{
	const bool safe = !w.empty() && std::all_of(w.begin(), w.end(), [](char c) {
		return std::isalnum(static_cast<unsigned char>(c)) || std::string("-_./=,:+@%").find(c) != std::string::npos;
	});
	if (safe) return w;
	std::string q = "'";
	for (const char c : w) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
	return q + "'";
}

std::string job_directory(const SweepPlan& plan, const SweepJob& job) { return plan.dir + "/" + job.dir; }

namespace
{
/** A given rawlog's group: its kind (range-bearing or inertial) and the ground truth next to it. */
SweepGroup rawlog_group(const std::string& r)
{
	check_input_file(r, "rawlog");
	SweepGroup g;
	g.rawlog = absolute(r);
	g.name = file_safe(rawlog_stem(r));
	g.inertial = io::is_observation_rawlog(g.rawlog);
	if (!g.inertial)
	{
		// Its first step, so that a file that is no rawlog fails here, not in every job.
		io::RawlogReaderOptions first;
		first.max_steps = 1;
		first.require_landmark_ids = false;
		first.probe_decoder = false;
		(void)io::read_rawlog(g.rawlog, first);
	}
	RunOptions gt_of;
	gt_of.rawlog = g.rawlog;
	const std::string gt = g.inertial ? inertial_ground_truth_path(gt_of) : eval::default_ground_truth_path(g.rawlog);
	if (!gt.empty() && fs::exists(gt)) g.ground_truth = gt;
	return g;
}
}  // namespace

SweepPlan plan_sweep(const SweepOptions& o)
{
	o.validate();
	SweepPlan plan;
	plan.kind = o.kind;
	plan.dir = absolute(o.dir);
	plan.windows = o.run.windows;
	plan.threads = o.run.window.solver.num_threads;
	if (!o.simulate_ini.empty())
	{
		// As swba simulate reads it, so that a file that is no simul-landmarks INI fails here, not in every job.
		(void)simulation_ini(read_text_file(o.simulate_ini, "simul-landmarks INI"), o.simulate_ini, 1, "check");
		plan.simulate_ini = absolute(o.simulate_ini);
		for (long seed : o.seeds)
		{
			SweepGroup g;
			g.seed = seed;
			SimulateOptions so;
			so.ini = o.simulate_ini;
			so.seed = seed;
			g.name = file_safe(so.output_name());
			plan.groups.push_back(g);
		}
	}
	std::set<std::string> names;
	for (const auto& r : o.rawlogs) plan.groups.push_back(rawlog_group(r));
	for (auto& g : plan.groups)
		if (!names.insert(g.name).second)
			throw std::invalid_argument("two rawlogs are named '" + g.name + "': run them as two sweeps");

	for (std::size_t gi = 0; gi < plan.groups.size(); gi++)
	{
		SweepGroup& g = plan.groups[gi];
		const bool one_job = o.kind == SweepKind::Nees || g.inertial;
		const std::vector<int> windows = one_job ? std::vector<int>{0} : o.run.windows;
		// The job of the widest window also runs the EKF, the batch and the causal row: the batch starts
		// from the widest window's lagged trajectory, as in one swba run of every window.
		const std::size_t full = static_cast<std::size_t>(std::max_element(windows.begin(), windows.end()) - windows.begin());
		for (std::size_t wi = 0; wi < windows.size(); wi++)
		{
			SweepJob job;
			job.id = plan.jobs.size() + 1;
			job.group = gi;
			job.window = windows[wi];
			job.dir = "jobs/" + g.name + "/" + (job.window ? "w" + std::to_string(job.window) : "all");
			job.command = run_command(plan, o.swba, g, job, wi == full);
			g.jobs.push_back(job.id);
			plan.jobs.push_back(job);
		}
	}
	return plan;
}

std::string format_job_list(const SweepPlan& plan)
{
	std::string s;
	for (const auto& j : plan.jobs) s += j.command + "\n";
	return s;
}

std::string format_sbatch_script(const SweepPlan& plan)
{
	const std::string jobs = plan.dir + "/jobs.txt";
	std::ostringstream s;
	s << "#!/bin/bash\n"
	  << "# Slurm job array of the swba sweep in " << plan.dir << " (written by swba): array task K runs\n"
	  << "# line K of jobs.txt. Submit: sbatch " << plan.dir << "/jobs.sbatch; when every task is done:\n"
	  << "# swba merge " << plan.dir << ". One task without Slurm: SLURM_ARRAY_TASK_ID=K bash jobs.sbatch.\n"
	  << "# Re-run failed tasks: sbatch --array=K,L,... " << plan.dir << "/jobs.sbatch\n"
	  << "#SBATCH --job-name=swba-" << (plan.kind == SweepKind::Nees ? "nees" : "sweep") << "\n"
	  << "#SBATCH --array=1-" << plan.jobs.size() << "\n"
	  << "#SBATCH --ntasks=1\n"
	  << "#SBATCH --cpus-per-task=" << plan.threads << "\n"
	  << "#SBATCH --output=" << plan.dir << "/slurm-%A_%a.out\n"
	  << "set -euo pipefail\n"
	  << "jobs=" << shell_quote(jobs) << "\n"
	  << "task=\"${SLURM_ARRAY_TASK_ID:?not set: submit with sbatch, or set it to a line number of $jobs}\"\n"
	  << "line=$(sed -n \"${task}p\" \"$jobs\")\n"
	  << "if [ -z \"$line\" ]; then echo \"jobs.sbatch: no line $task in $jobs\" >&2; exit 2; fi\n"
	  << "echo \"jobs.sbatch: task $task: $line\" >&2\n"
	  << "exec bash -c \"$line\"\n";
	return s.str();
}

std::string format_sweep_manifest(const SweepPlan& plan)
{
	ordered_json groups = ordered_json::array();
	for (const auto& g : plan.groups)
		groups.push_back({{"name", g.name},
						  {"rawlog", string_or_null(g.rawlog)},
						  {"ground_truth", string_or_null(g.ground_truth)},
						  {"seed", nonzero_or_null(g.seed)},
						  {"inertial", g.inertial},
						  {"jobs", g.jobs}});
	ordered_json jobs = ordered_json::array();
	for (const auto& job : plan.jobs)
		jobs.push_back({{"id", job.id},
						{"group", plan.groups[job.group].name},
						{"window", nonzero_or_null(job.window)},
						{"dir", job.dir},
						{"command", job.command}});
	const ordered_json j = {{"kind", enum_name(plan.kind)},
							{"simulate_ini", string_or_null(plan.simulate_ini)},
							{"windows", plan.windows},
							{"threads", plan.threads},
							{"groups", groups},
							{"jobs", jobs}};
	return j.dump(2, ' ', false, ordered_json::error_handler_t::replace) + "\n";
}

void write_sweep(const SweepOptions& options, const SweepPlan& plan, std::ostream& log, bool say_how_to_run,
				 const std::string& program)
{
	std::error_code ec;
	fs::create_directories(plan.dir, ec);
	if (ec) throw std::runtime_error("cannot create sweep directory '" + plan.dir + "': " + ec.message());
	auto write = [&](const std::string& name, const std::string& text) {
		write_text_file_atomically(plan.dir + "/" + name, text);
	};
	const std::string header = "# swba sweep: the swba run options of ";
	write(kRunConfig, header + "each rawlog's job of the widest W (load with swba run --config)\n" +
						  format_run_config(job_run_options(options.run, true)));
	write(kWindowsConfig, header + "the other jobs: EKF, batch and causal off\n" +
							  format_run_config(job_run_options(options.run, false)));
	write("jobs.txt", format_job_list(plan));
	write("jobs.sbatch", format_sbatch_script(plan));
	write("sweep.json", format_sweep_manifest(plan));
	if (!say_how_to_run) return;
	log << program << ": wrote " << plan.jobs.size() << " jobs into " << plan.dir << "/jobs.txt. Run them with\n"
		<< "  parallel -j 2 --joblog " << plan.dir << "/joblog --bar < " << plan.dir << "/jobs.txt\n"
		<< "or on Slurm: sbatch " << plan.dir << "/jobs.sbatch; then: swba merge " << plan.dir << "\n";
}

SweepPlan read_sweep_manifest(const std::string& dir)
{
	const std::string path = dir + "/sweep.json";
	std::ifstream f = open_input_file(path, std::ios::in, "sweep manifest");
	SweepPlan plan;
	plan.dir = absolute(dir);
	try
	{
		const ordered_json j = ordered_json::parse(f);
		plan.kind = parse_enum<SweepKind>(j.at("kind").get<std::string>(), "sweep kind");
		if (!j.at("simulate_ini").is_null()) plan.simulate_ini = j.at("simulate_ini").get<std::string>();
		plan.windows = j.at("windows").get<std::vector<int>>();
		plan.threads = j.value("threads", 1);
		std::map<std::string, std::size_t> group_of;
		for (const auto& e : j.at("groups"))
		{
			SweepGroup g;
			g.name = e.at("name").get<std::string>();
			if (!e.at("rawlog").is_null()) g.rawlog = e.at("rawlog").get<std::string>();
			if (!e.at("ground_truth").is_null()) g.ground_truth = e.at("ground_truth").get<std::string>();
			if (!e.at("seed").is_null()) g.seed = e.at("seed").get<long>();
			g.inertial = e.value("inertial", false);
			g.jobs = e.at("jobs").get<std::vector<std::size_t>>();
			group_of[g.name] = plan.groups.size();
			plan.groups.push_back(g);
		}
		for (const auto& e : j.at("jobs"))
		{
			SweepJob job;
			job.id = e.at("id").get<std::size_t>();
			const std::string group = e.at("group").get<std::string>();
			if (!group_of.count(group)) throw std::runtime_error("job " + std::to_string(job.id) + ": unknown group '" + group + "'");
			job.group = group_of[group];
			job.window = e.at("window").is_null() ? 0 : e.at("window").get<int>();
			job.dir = e.at("dir").get<std::string>();
			job.command = e.at("command").get<std::string>();
			if (job.id != plan.jobs.size() + 1) throw std::runtime_error("job ids must be 1, 2, ... in order");
			plan.jobs.push_back(job);
		}
		for (const auto& g : plan.groups)
			for (std::size_t id : g.jobs)
				if (id < 1 || id > plan.jobs.size())
					throw std::runtime_error("group '" + g.name + "': no job " + std::to_string(id));
	}
	catch (const nlohmann::json::exception& e)
	{
		throw std::runtime_error("sweep manifest '" + path + "': " + e.what());
	}
	catch (const std::exception& e)
	{
		throw std::runtime_error("sweep manifest '" + path + "': " + e.what());
	}
	return plan;
}

namespace
{
/** The job of group `g` that runs the EKF, batch and causal rows: the first of its widest window. */
std::size_t full_job_of(const SweepPlan& plan, std::size_t g)
{
	std::size_t best = 0;
	int widest = -1;
	for (std::size_t id : plan.groups[g].jobs)
	{
		const SweepJob& j = plan.jobs[id - 1];
		if (j.window > widest)
		{
			widest = j.window;
			best = id;
		}
	}
	return best;
}

/** The rows a job's summary.json has when the job ran to its end: a job stopped half-way (killed) leaves
 * the summary of the estimators it completed, which must not pass for a complete one. */
std::size_t expected_rows(const RunOptions& o, const SweepJob& job)
{
	const std::size_t windows = job.window ? 1 : o.windows.size();
	// The batch runs from dead reckoning and, after a window, from its lagged trajectory (two rows).
	const std::size_t batch = o.run_batch ? (windows > 0 ? 2 : 1) : 0;
	return (o.run_ekf ? o.ekf_methods.size() : 0) + o.policies.size() * o.fej.size() * windows * 2 + batch +
		   (o.run_causal ? 1 : 0);
}

/** Why the summary `j` (parsed, or discarded when not JSON) of a job is not complete ("" when it is).
 * An inertial job's: swba run writes it once, after every row; none interrupted (a stop request between
 * estimators). A range-bearing job's: `expected` estimator rows, none interrupted. */
std::string summary_problem(const ordered_json& j, bool inertial, std::size_t expected)
{
	if (inertial)
	{
		if (j.is_discarded() || j.value("kind", "") != "inertial" || !j.contains("rows") || !j["rows"].is_array())
			return "summary.json is not a swba run summary of an inertial rawlog";
		for (const auto& e : j["rows"])
			if (e.value("interrupted", false)) return "interrupted";
		return "";
	}
	if (j.is_discarded() || !j.contains("estimators") || !j["estimators"].is_array())
		return "summary.json is not a swba run summary";
	for (const auto& e : j["estimators"])
		if (e.value("interrupted", false)) return "interrupted";
	if (j["estimators"].size() != expected)
		return "summary.json has " + std::to_string(j["estimators"].size()) + " estimator rows, expected " +
			   std::to_string(expected) + " (the job stopped before its end)";
	return "";
}
}  // namespace

void check_jobs_complete(const SweepPlan& plan, std::ostream& log) { read_complete_jobs(plan, log); }

std::vector<JobSummary> read_complete_jobs(const SweepPlan& plan, std::ostream& log)
{
	RunOptions first_config, other_config;
	load_run_config(plan.dir + "/" + kRunConfig, first_config);
	if (plan.kind == SweepKind::Run) load_run_config(plan.dir + "/" + kWindowsConfig, other_config);
	std::vector<JobSummary> summaries;
	std::vector<std::string> missing;
	std::size_t first = 0;
	for (const auto& job : plan.jobs)
	{
		const bool first_of_group = full_job_of(plan, job.group) == job.id;
		const std::size_t expected = expected_rows(first_of_group ? first_config : other_config, job);
		JobSummary& s = summaries.emplace_back();
		s.dir = job_directory(plan, job);
		s.path = s.dir + "/summary.json";
		std::string why = "no summary.json";
		if (fs::is_regular_file(s.path))
		{
			std::ifstream f(s.path);
			s.json = ordered_json::parse(f, nullptr, false);
			why = summary_problem(s.json, plan.groups[job.group].inertial, expected);
		}
		if (why.empty()) continue;
		if (missing.empty()) first = job.id;
		missing.push_back("job " + std::to_string(job.id) + " (" + job.dir + "): " + why);
	}
	if (missing.empty()) return summaries;
	for (const auto& m : missing) log << "swba merge: " << m << "\n";
	throw std::runtime_error("sweep '" + plan.dir + "': " + std::to_string(missing.size()) + " of " +
							 std::to_string(plan.jobs.size()) +
							 " jobs are not complete (not run, running or failed; listed above). Re-run one (job K "
							 "is line K of jobs.txt): sed -n " + std::to_string(first) + "p " + plan.dir +
							 "/jobs.txt | bash; the failed ones of a GNU parallel run: parallel --retry-failed "
							 "--joblog " + plan.dir + "/joblog");
}
}  // namespace swba::apps
