// swba_bench_bal: swba's Levenberg-Marquardt vs Ceres 2.1 on BAL problems, in one run, with the same
// thread count, tolerances and initial values. Every solve runs in its own forked process so that
// its peak RSS (getrusage) is its own and no run warms the caches of the next.
//
// For each problem: Ceres SPARSE_SCHUR and DENSE_SCHUR, swba sparse-schur and dense-schur, each run
// to the iteration limit; the target cost is Ceres SPARSE_SCHUR's final cost × (1 + rel_tol); swba's
// time to the target is measured by a separate run with SolverOptions::stop_at_cost = target, Ceres's
// from its iteration log (cumulative time at the first iteration whose cost is ≤ target).
// Times are medians over --repeat repetitions, the configurations interleaved.
#include <swba/eval/text_format.h>

#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "bal_peers.h"

namespace
{
using swba::bench::PeerResult;
using swba::bench::PeerSettings;

struct Config
{
	std::string name;
	bool ceres = false;
	bool dense = false;
	bool to_target = false;  ///< swba run stopped at the target cost
};

struct RunResult
{
	PeerResult peer;
	long peak_rss_kb = 0;
	long rss_before_solve_kb = 0;
	double cpu_s = 0;  ///< user + system CPU time of the whole child (read + build + solve)
};

long current_rss_kb()
{
	std::ifstream f("/proc/self/statm");
	long pages_total = 0, pages_resident = 0;
	f >> pages_total >> pages_resident;
	return pages_resident * (sysconf(_SC_PAGESIZE) / 1024);
}

/** The child's work: reads the problem, solves it with the configuration's peer and reports the
 * figures as "key value" lines ("error <what>" if anything throws). */
std::string child_report(const std::string& path, const Config& c, const PeerSettings& settings)
{
	std::ostringstream out;
	out.precision(17);
	try
	{
		const auto bal = swba::io::read_bal(path);
		PeerSettings s = settings;
		s.dense = c.dense;
		const long rss_before = current_rss_kb();
		PeerResult r;
#ifdef SWBA_HAVE_CERES
		r = c.ceres ? swba::bench::solve_ceres(bal, s) : swba::bench::solve_swba(bal, s);
#else
		r = swba::bench::solve_swba(bal, s);
#endif
		rusage ru{};
		getrusage(RUSAGE_SELF, &ru);
		const double cpu = ru.ru_utime.tv_sec + 1e-6 * ru.ru_utime.tv_usec + ru.ru_stime.tv_sec + 1e-6 * ru.ru_stime.tv_usec;
		out << "ok 1\ncpu " << cpu << "\nrss " << ru.ru_maxrss << "\nrss_before " << rss_before << "\ninitial " << r.initial_cost
			<< "\nfinal " << r.final_cost << "\niterations " << r.iterations << "\ntime " << r.solve_time_s << "\n";
		for (const auto& it : r.log) out << "iter " << it.iteration << " " << it.cost << " " << it.cumulative_time_s << "\n";
		out << "termination " << r.termination << "\n";
	}
	catch (const std::exception& e)
	{
		out << "error " << e.what() << "\n";
	}
	return out.str();
}

/** Parses child_report()'s lines; throws with the configuration's name on an error or no result. */
RunResult parse_child_report(const std::string& text, const std::string& name)
{
	RunResult rr;
	std::istringstream in(text);
	std::string key;
	bool ok = false;
	while (in >> key)
	{
		if (key == "error")
		{
			std::string rest;
			std::getline(in, rest);
			throw std::runtime_error(name + ":" + rest);
		}
		if (key == "ok") in >> ok;
		else if (key == "rss") in >> rr.peak_rss_kb;
		else if (key == "cpu") in >> rr.cpu_s;
		else if (key == "rss_before") in >> rr.rss_before_solve_kb;
		else if (key == "initial") in >> rr.peer.initial_cost;
		else if (key == "final") in >> rr.peer.final_cost;
		else if (key == "iterations") in >> rr.peer.iterations;
		else if (key == "time") in >> rr.peer.solve_time_s;
		else if (key == "iter")
		{
			swba::bench::PeerIteration it;
			in >> it.iteration >> it.cost >> it.cumulative_time_s;
			rr.peer.log.push_back(it);
		}
		else if (key == "termination")
		{
			std::getline(in, rr.peer.termination);
			if (!rr.peer.termination.empty() && rr.peer.termination[0] == ' ') rr.peer.termination.erase(0, 1);
		}
	}
	if (!ok) throw std::runtime_error(name + ": no result from the child process");
	return rr;
}

// Runs one solve in a child process; the child reads the problem itself.
RunResult run_in_child(const std::string& path, const Config& c, const PeerSettings& settings)
{
	std::cout.flush();
	std::fflush(nullptr);
	int fds[2];
	if (pipe(fds) != 0) throw std::runtime_error("pipe failed");
	const pid_t pid = fork();
	if (pid < 0) throw std::runtime_error("fork failed");
	if (pid == 0)
	{
		close(fds[0]);
		const std::string msg = child_report(path, c, settings);
		size_t done = 0;
		while (done < msg.size())
		{
			const ssize_t w = write(fds[1], msg.data() + done, msg.size() - done);
			if (w <= 0) break;
			done += static_cast<size_t>(w);
		}
		close(fds[1]);
		_exit(0);
	}
	close(fds[1]);
	std::string text;
	char buf[4096];
	ssize_t n;
	while ((n = read(fds[0], buf, sizeof(buf))) > 0) text.append(buf, static_cast<size_t>(n));
	close(fds[0]);
	int status = 0;
	waitpid(pid, &status, 0);
	if (!WIFEXITED(status)) throw std::runtime_error(c.name + ": child process crashed");
	return parse_child_report(text, c.name);
}

/** Cumulative time at the first logged iteration with cost ≤ target; -1 if never. */
double time_to_target_from_log(const PeerResult& r, double target)
{
	for (const auto& it : r.log)
		if (it.cost <= target) return it.cumulative_time_s;
	return -1;
}

double median(std::vector<double> v)
{
	v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return x < 0; }), v.end());
	if (v.empty()) return -1;
	std::sort(v.begin(), v.end());
	const size_t m = v.size() / 2;
	return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

/** A table cell: `v` by the printf conversion `f`. */
std::string fmt(const char* f, double v) { return swba::eval::format_printf(f, v); }

struct BenchCommandLine
{
	TCLAP::CmdLine cmd{
		"BAL benchmark: swba vs Ceres 2.1 (SPARSE_SCHUR, DENSE_SCHUR) on the same problems, threads and tolerances.",
		' ', "0.1.0"};
	TCLAP::UnlabeledMultiArg<std::string> problems{
		"problems", "BAL files (default: share/data/bal/problem-49-7776-pre.txt)", false, "FILE", cmd};
	TCLAP::ValueArg<int> threads{"", "threads", "threads for every solver (default 2)", false, 2, "N", cmd};
	TCLAP::ValueArg<int> repeat{"", "repeat", "repetitions; times are medians (default 3)", false, 3, "R", cmd};
	TCLAP::ValueArg<int> max_iter{
		"", "max-iterations", "LM iteration limit (default 50, Ceres's default)", false, 50, "K", cmd};
	TCLAP::ValueArg<double> ftol{"", "function-tolerance",
								 "relative cost change tolerance (default 1e-15: run to the iteration limit)", false,
								 1e-15, "TOL", cmd};
	TCLAP::ValueArg<double> gtol{"", "gradient-tolerance", "default 1e-15", false, 1e-15, "TOL", cmd};
	TCLAP::ValueArg<double> ptol{"", "parameter-tolerance", "default 1e-15", false, 1e-15, "TOL", cmd};
	TCLAP::ValueArg<double> rtol{"", "target-tolerance",
								 "target = Ceres SPARSE_SCHUR final cost × (1 + this) (default 1e-6)", false, 1e-6,
								 "REL", cmd};
	TCLAP::SwitchArg no_dense{"", "no-dense", "skip the DENSE_SCHUR / dense-schur runs", cmd};
};

std::vector<Config> make_configs(bool no_dense)
{
	std::vector<Config> configs;
#ifdef SWBA_HAVE_CERES
	configs.push_back({"Ceres SPARSE_SCHUR", true, false, false});
	if (!no_dense) configs.push_back({"Ceres DENSE_SCHUR", true, true, false});
#else
	std::cout << "(built without Ceres: swba runs only, no target cost)\n";
#endif
	configs.push_back({"swba sparse-schur", false, false, false});
	if (!no_dense) configs.push_back({"swba dense-schur", false, true, false});
	return configs;
}

/** Every run of one problem: per configuration, the full runs and (swba) the runs to the target. */
struct ProblemRuns
{
	std::vector<std::vector<RunResult>> full, to_target;
	double target = -1;
};

ProblemRuns run_problem(const std::string& path, const std::vector<Config>& configs, const PeerSettings& settings,
						int repeat, double rtol)
{
	const size_t nc = configs.size();
	ProblemRuns runs;
	runs.full.resize(nc);
	runs.to_target.resize(nc);
	for (int rep = 0; rep < repeat; rep++)
	{
		for (size_t c = 0; c < nc; c++)
		{
			runs.full[c].push_back(run_in_child(path, configs[c], settings));
			if (configs[c].ceres && !configs[c].dense && runs.target < 0)
				runs.target = runs.full[c].back().peer.final_cost * (1.0 + rtol);
		}
		for (size_t c = 0; c < nc; c++)
		{
			if (configs[c].ceres || runs.target < 0) continue;
			PeerSettings s = settings;
			s.stop_at_cost = runs.target;
			runs.to_target[c].push_back(run_in_child(path, configs[c], s));
		}
	}
	return runs;
}

/** Medians over the repetitions of one configuration; times to target: Ceres from its log, swba from
 * the stop_at_cost runs. */
struct ConfigFigures
{
	double t_full = -1, t_target = -1, rss_mib = 0, cpu = -1;
};

ConfigFigures figures_of(const Config& config, const std::vector<RunResult>& full,
						 const std::vector<RunResult>& to_target, double target)
{
	std::vector<double> tf, tt, tc;
	long peak = 0;
	for (const auto& r : full)
	{
		tf.push_back(r.peer.solve_time_s);
		tc.push_back(r.cpu_s);
		if (config.ceres) tt.push_back(time_to_target_from_log(r.peer, target));
		peak = std::max(peak, r.peak_rss_kb);
	}
	for (const auto& r : to_target) tt.push_back(r.peer.final_cost <= target ? r.peer.solve_time_s : -1);
	return {median(tf), median(tt), peak / 1024.0, median(tc)};
}

void print_table(const std::vector<Config>& configs, const ProblemRuns& runs, const std::vector<ConfigFigures>& f,
				 double rtol)
{
	const size_t nc = configs.size();
	double ceres_sparse_t = -1, ceres_best_t = -1;
	for (size_t c = 0; c < nc; c++)
		if (configs[c].ceres && f[c].t_target > 0)
		{
			if (!configs[c].dense) ceres_sparse_t = f[c].t_target;
			if (ceres_best_t < 0 || f[c].t_target < ceres_best_t) ceres_best_t = f[c].t_target;
		}
	std::cout << "target cost (Ceres SPARSE_SCHUR final × (1+" << rtol << ")): " << fmt("%.6f", runs.target) << "\n\n";
	std::cout << "| solver | initial cost | final cost | iterations | time [s] | CPU [s] | time to target [s] | ratio vs "
				 "Ceres SPARSE_SCHUR | ratio vs fastest Ceres | peak RSS [MiB] |\n";
	std::cout << "|---|---|---|---|---|---|---|---|---|---|\n";
	for (size_t c = 0; c < nc; c++)
	{
		const auto& r0 = runs.full[c].front().peer;
		const double tt = f[c].t_target;
		std::cout << "| " << configs[c].name << " | " << fmt("%.6e", r0.initial_cost) << " | "
				  << fmt("%.6f", r0.final_cost) << " | " << r0.iterations << " | " << fmt("%.3f", f[c].t_full) << " | "
				  << fmt("%.3f", f[c].cpu) << " | " << (tt > 0 ? fmt("%.3f", tt) : std::string("not reached")) << " | "
				  << (tt > 0 && ceres_sparse_t > 0 ? fmt("%.2f", tt / ceres_sparse_t) : std::string("-")) << " | "
				  << (tt > 0 && ceres_best_t > 0 ? fmt("%.2f", tt / ceres_best_t) : std::string("-")) << " | "
				  << fmt("%.1f", f[c].rss_mib) << " |\n";
	}
}

void print_runs(const std::vector<Config>& configs, const ProblemRuns& runs)
{
	std::cout << "\nper-run times [s] (full runs; swba to-target runs in brackets):\n";
	for (size_t c = 0; c < configs.size(); c++)
	{
		std::cout << "  " << configs[c].name << ":";
		for (const auto& r : runs.full[c]) std::cout << " " << fmt("%.3f", r.peer.solve_time_s);
		if (!runs.to_target[c].empty())
		{
			std::cout << " [";
			for (const auto& r : runs.to_target[c])
				std::cout << " " << fmt("%.3f", r.peer.solve_time_s) << "@" << r.peer.iterations << "it";
			std::cout << " ]";
		}
		std::cout << "  (" << runs.full[c].front().peer.termination << ")\n";
	}
	for (size_t c = 0; c < configs.size(); c++)
		if (configs[c].ceres)
			for (const auto& it : runs.full[c].front().peer.log)
				if (it.cost <= runs.target)
				{
					std::cout << "  " << configs[c].name << " reaches the target at iteration " << it.iteration << "\n";
					break;
				}
	std::cout << "\n";
}

int run(int argc, char** argv)
{
	BenchCommandLine args;
	try
	{
		if (!args.cmd.parse(argc, argv)) return 0;
	}
	catch (const TCLAP::ArgException& e)
	{
		std::cerr << "swba_bench_bal: " << e.error() << " (" << e.argId() << ")\n";
		return 2;
	}
	std::vector<std::string> files = args.problems.getValue();
	if (files.empty()) files.push_back(std::string(SWBA_DATA_DIR) + "/bal/problem-49-7776-pre.txt");

	PeerSettings settings;
	settings.num_threads = args.threads.getValue();
	settings.max_iterations = args.max_iter.getValue();
	settings.function_tolerance = args.ftol.getValue();
	settings.gradient_tolerance = args.gtol.getValue();
	settings.parameter_tolerance = args.ptol.getValue();
	const std::vector<Config> configs = make_configs(args.no_dense.getValue());

	for (const auto& path : files)
	{
		const auto bal = swba::io::read_bal(path);
		std::cout << "# " << path << ": " << bal.num_cameras << " cameras, " << bal.num_points << " points, "
				  << bal.observations.size() << " observations; threads " << settings.num_threads << ", max "
				  << settings.max_iterations << " iterations, tolerances f " << settings.function_tolerance << " g "
				  << settings.gradient_tolerance << " p " << settings.parameter_tolerance << ", "
				  << args.repeat.getValue() << " repetitions\n";
		const ProblemRuns runs = run_problem(path, configs, settings, args.repeat.getValue(), args.rtol.getValue());
		std::vector<ConfigFigures> figures;
		for (size_t c = 0; c < configs.size(); c++)
			figures.push_back(figures_of(configs[c], runs.full[c], runs.to_target[c], runs.target));
		print_table(configs, runs, figures, args.rtol.getValue());
		print_runs(configs, runs);
	}
	return 0;
}
}  // namespace

int main(int argc, char** argv)
{
	try
	{
		return run(argc, argv);
	}
	catch (const std::exception& e)
	{
		std::cerr << "swba_bench_bal: error: " << e.what() << "\n";
		return 1;
	}
}
