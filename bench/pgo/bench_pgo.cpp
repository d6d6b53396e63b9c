// swba_bench_pgo: solves the same g2o pose graphs with swba::solve, with Ceres 2.1 on the same reference
// model (when built with Ceres) and with MRPT's graphslam::optimize_graph_spa_levmarq (when built with
// mrpt-graphslam), in one run. Every final cost is re-evaluated with swba::problems::pose_graph_cost,
// the reference ½ Σ rᵀΛr of doc/pgo.md, so the numbers are comparable whatever each solver reports.
//
// Usage: swba_bench_pgo [--threads N] [--max-iterations K] [--repeat R] [--mrpt-max-iterations K] [--init LIST]
//                       [--initial-trust-region MU0] [--no-ceres-tr] [--no-mrpt] [--no-ceres] [graph.g2o ...]
// Without graphs: sphere2500, parking-garage, smallGrid3D and intel from SWBA_DATA_DIR/posegraph.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "pgo_peers.h"

namespace
{
using swba::bench::Result;
using swba::bench::Settings;

const char* const kUsage =
	"usage: swba_bench_pgo [--threads N] [--max-iterations K] [--repeat R] [--mrpt-max-iterations K]\n"
	"                      [--model g2o|ceres|both] [--init LIST] [--initial-trust-region MU0] [--no-ceres-tr]\n"
	"                      [--no-mrpt] [--no-ceres] [graph.g2o ...]\n"
	"  --init: comma-separated swba initialisations among chordal, odometry, file, chordal-rot (chordal rotations,\n"
	"          positions composed along the odometry tree) (default chordal,odometry)\n"
	"  --initial-trust-region: swba's initial LM radius (default 1e12, as swba pgo), also used by the ceres:tr row\n"
	"  --no-ceres-tr: omit the ceres:tr row (Ceres from the file with swba's initial radius)\n";

const char* model_name(swba::RotationError m) { return m == swba::RotationError::G2o ? "g2o" : "ceres"; }

int parse_int(const char* s, const char* name)
{
	char* end = nullptr;
	const long v = std::strtol(s, &end, 10);
	if (!s[0] || *end || v < 1)
	{
		std::fprintf(stderr, "swba_bench_pgo: %s needs a positive integer, got '%s'\n", name, s);
		std::exit(2);
	}
	return static_cast<int>(v);
}

/** --init LIST; false (after the message) on an unknown name. */
bool parse_inits(const std::string& list, Settings& s)
{
	s.inits.clear();
	for (size_t pos = 0; pos <= list.size();)
	{
		const size_t comma = std::min(list.find(',', pos), list.size());
		try
		{
			const std::string name = list.substr(pos, comma - pos);
			if (name == "chordal-rot") s.inits.emplace_back(swba::problems::PoseGraphInit::Chordal, false);
			else s.inits.emplace_back(swba::problems::parse_pose_graph_init(name), true);
		}
		catch (const std::invalid_argument& e)
		{
			std::fprintf(stderr, "swba_bench_pgo: --init: %s\n", e.what());
			return false;
		}
		pos = comma + 1;
	}
	return true;
}

/** Options with a value; false (after the message) on a bad value. */
bool parse_valued_option(const std::string& a, const char* value, Settings& s)
{
	if (a == "--threads") s.threads = parse_int(value, "--threads");
	else if (a == "--max-iterations") s.max_iterations = parse_int(value, "--max-iterations");
	else if (a == "--repeat") s.repeat = parse_int(value, "--repeat");
	else if (a == "--mrpt-max-iterations") s.mrpt_max_iterations = parse_int(value, "--mrpt-max-iterations");
	else if (a == "--model")
	{
		const std::string m = value;
		if (m == "both") s.models = {swba::RotationError::G2o, swba::RotationError::CeresExample};
		else if (m == "g2o" || m == "ceres") s.models = {swba::problems::parse_rotation_error(m)};
		else
		{
			std::fprintf(stderr, "swba_bench_pgo: --model expects g2o, ceres or both\n");
			return false;
		}
	}
	else if (a == "--init") return parse_inits(value, s);
	else if (a == "--initial-trust-region")
	{
		s.initial_trust_region = std::atof(value);
		if (!(s.initial_trust_region > 0))
		{
			std::fprintf(stderr, "swba_bench_pgo: --initial-trust-region needs a positive number\n");
			return false;
		}
	}
	return true;
}

/** The settings, or the exit code (0 after --help, 2 on a bad command line). */
std::optional<int> parse_settings(int argc, char** argv, Settings& s)
{
	for (int i = 1; i < argc; i++)
	{
		const std::string a = argv[i];
		if (a == "--threads" || a == "--max-iterations" || a == "--repeat" || a == "--mrpt-max-iterations" ||
			a == "--model" || a == "--init" || a == "--initial-trust-region")
		{
			if (i + 1 >= argc)
			{
				std::fprintf(stderr, "swba_bench_pgo: %s needs a value\n", a.c_str());
				return 2;
			}
			if (!parse_valued_option(a, argv[++i], s)) return 2;
		}
		else if (a == "--no-ceres-tr") s.run_ceres_tr = false;
		else if (a == "--no-mrpt") s.run_mrpt = false;
		else if (a == "--no-ceres") s.run_ceres = false;
		else if (a == "--help" || a == "-h")
		{
			std::printf("%s", kUsage);
			return 0;
		}
		else if (!a.empty() && a[0] == '-')
		{
			std::fprintf(stderr, "swba_bench_pgo: unknown option %s\n%s", a.c_str(), kUsage);
			return 2;
		}
		else s.graphs.push_back(a);
	}
	if (s.graphs.empty())
		for (const char* n : {"sphere2500", "parking-garage", "smallGrid3D", "intel"})
			s.graphs.push_back(std::string(SWBA_DATA_DIR) + "/posegraph/" + n + ".g2o");
	return std::nullopt;
}

void print_header(const Settings& s)
{
	std::printf("swba_bench_pgo: threads %d, max iterations %d, best of %d; ceres %s, mrpt graphslam %s\n",
				s.threads, s.max_iterations, s.repeat,
#ifdef SWBA_BENCH_HAVE_CERES
				s.run_ceres ? "on" : "off",
#else
				"not built",
#endif
#ifdef SWBA_BENCH_HAVE_MRPT_GRAPHSLAM
				s.run_mrpt ? "on" : "off"
#else
				"not built"
#endif
	);
	std::printf("final cost = 1/2 sum r^T Lambda r of the model's residual (doc/pgo.md), recomputed for every solver;\n"
				"model g2o: rotation error 2 vec(q_ab^-1 q_a^-1 q_b); model ceres: 2 vec(q_ab (q_a^-1 q_b)^-1)\n"
				"(2D graphs have one model). Times: wall clock, best of the repeats; setup = building the solver's\n"
				"problem (not in solve). swba:chor / swba:odom / swba:file = swba::solve started from the chordal\n"
				"initialisation / odometry composition / the file's values (swba:chor-r: chordal rotations, odometry-\n"
				"composed positions); for swba, solve[s] INCLUDES the\n"
				"initialisation (init[s]). ceres and mrpt start from the file's values; ceres = Ceres's default options\n"
				"(initial trust region 1e4), ceres:tr = Ceres with swba's initial trust region (%.0e).\n"
				"ours/ceres = swba's solve[s] (initialisation + LM) / the 'ceres' row's Solve() time (default options),\n"
				"same model; ours/c:tr = the same over the 'ceres:tr' row. start cost = cost where the solver starts.\n\n",
				s.initial_trust_region);
	std::printf("%-15s %-5s %-9s %13s %16s %16s %5s %8s %8s %8s %10s %9s\n", "graph", "model", "solver", "start cost",
				"final cost", "solver's cost", "iters", "setup[s]", "init[s]", "solve[s]", "ours/ceres", "ours/c:tr");
}

/** Every solver's result on `g` under one model (mrpt's, computed once, re-evaluated under it). */
std::vector<Result> run_solvers(const swba::io::PoseGraph& g, const Settings& s, swba::RotationError model,
								const Result& mrpt)
{
	std::vector<Result> results;
	for (const auto& [init, positions] : s.inits)
		results.push_back(swba::bench::run_swba(g, s, model, init, positions));
#ifdef SWBA_BENCH_HAVE_CERES
	if (s.run_ceres) results.push_back(swba::bench::run_ceres(g, s, model, -1));
	if (s.run_ceres && s.run_ceres_tr) results.push_back(swba::bench::run_ceres(g, s, model, s.initial_trust_region));
#endif
	if (!mrpt.solver.empty())
	{
		results.push_back(mrpt);
		if (mrpt.final_cost >= 0) results.back().final_cost = swba::problems::pose_graph_cost(mrpt.solution, model);
	}
	return results;
}

const Result* find_solver(const std::vector<Result>& results, const char* solver)
{
	for (const auto& r : results)
		if (r.solver == solver) return &r;
	return nullptr;
}

/** One table row per result, their notes and the relative final-cost differences of swba vs ceres. */
void print_rows(const std::string& name, const char* mname, double initial, const std::vector<Result>& results,
				std::vector<std::string>& notes)
{
	const Result* ceres = find_solver(results, "ceres");
	const Result* ceres_tr = find_solver(results, "ceres:tr");
	for (const auto& r : results)
	{
		char ratio[32] = "", ratio_tr[32] = "";
		const bool ours = r.solver.rfind("swba", 0) == 0;
		if (ceres && ours && ceres->solve_s > 0) std::snprintf(ratio, sizeof ratio, "%.2f", r.solve_s / ceres->solve_s);
		if (ceres_tr && ours && ceres_tr->solve_s > 0)
			std::snprintf(ratio_tr, sizeof ratio_tr, "%.2f", r.solve_s / ceres_tr->solve_s);
		const double start = r.start_cost >= 0 ? r.start_cost : initial;
		char init_s[16] = "-";
		if (ours) std::snprintf(init_s, sizeof init_s, "%.3f", r.init_s);
		if (r.final_cost < 0)
			std::printf("%-15s %-5s %-9s %13.6e %16s %16s %5s %8s %8s %8s %10s  %s\n", name.c_str(), mname,
						r.solver.c_str(), start, "-", "-", "-", "-", "-", "-", "", r.note.c_str());
		else
			std::printf("%-15s %-5s %-9s %13.6e %16.10g %16.10g %5d %8.3f %8s %8.3f %10s %9s\n", name.c_str(), mname,
						r.solver.c_str(), start, r.final_cost, r.reported_cost, r.iterations, r.setup_s, init_s,
						r.solve_s, ratio, ratio_tr);
		if (!r.note.empty() && r.final_cost >= 0) notes.push_back(name + " " + mname + " " + r.solver + ": " + r.note);
	}
	if (ceres && ceres->final_cost > 0)
		for (const auto& r : results)
			if (r.solver.rfind("swba", 0) == 0)
			{
				char buf[64];
				std::snprintf(buf, sizeof buf, "%+.2e", (r.final_cost - ceres->final_cost) / ceres->final_cost);
				notes.push_back(name + " " + mname + ": relative final-cost difference " + r.solver + " vs ceres " + buf);
			}
}

/** The rows of one graph file under each model; false if the file cannot be read. */
bool bench_graph(const std::string& path, const Settings& s)
{
	swba::io::PoseGraph g;
	try
	{
		g = swba::io::read_g2o(path);
	}
	catch (const std::exception& e)
	{
		std::fprintf(stderr, "%s\n", e.what());
		return false;
	}
	std::string name = path.substr(path.find_last_of('/') + 1);
	if (name.size() > 4 && name.substr(name.size() - 4) == ".g2o") name.resize(name.size() - 4);
	std::vector<swba::RotationError> models = s.models;
	if (g.is_2d()) models = {swba::RotationError::G2o};  // the rotation convention is 3D only

	std::vector<std::string> notes;
	Result mrpt;
#ifdef SWBA_BENCH_HAVE_MRPT_GRAPHSLAM
	if (s.run_mrpt) mrpt = swba::bench::run_mrpt(g, s);
#endif
	for (const auto model : models)
	{
		const char* mname = g.is_2d() ? "2d" : model_name(model);
		const double initial = swba::problems::pose_graph_cost(g, model);
		print_rows(name, mname, initial, run_solvers(g, s, model, mrpt), notes);
		std::fflush(stdout);
	}
	for (const auto& n : notes) std::printf("    %s\n", n.c_str());
	return true;
}
}  // namespace

int main(int argc, char** argv)
{
	Settings s;
	if (const auto rc = parse_settings(argc, argv, s)) return *rc;
	print_header(s);
	int rc = 0;
	for (const auto& path : s.graphs)
		if (!bench_graph(path, s)) rc = 1;
	return rc;
}
