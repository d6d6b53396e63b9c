// swba_bench_pgo: solves the same g2o pose graphs with swba::solve, with Ceres 2.1 on the same reference
// model (when built with Ceres) and with MRPT's graphslam::optimize_graph_spa_levmarq (when built with
// mrpt-graphslam), in one run. Every final cost is re-evaluated with swba::io::pose_graph_cost, the
// reference ½ Σ rᵀΛr of doc/pgo.md, so the numbers are comparable whatever each solver reports.
//
// Usage: swba_bench_pgo [--threads N] [--max-iterations K] [--repeat R] [--mrpt-max-iterations K] [--init LIST]
//                       [--initial-trust-region MU0] [--no-ceres-tr] [--no-mrpt] [--no-ceres] [graph.g2o ...]
// Without graphs: sphere2500, parking-garage, smallGrid3D and intel from SWBA_DATA_DIR/posegraph.
#include <swba/io/g2o.h>
#include <swba/io/g2o_init.h>
#include <swba/nonlinear/solver.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <iostream>
#include <map>
#include <set>
#include <string>
#include <vector>

#ifdef SWBA_BENCH_HAVE_CERES
#include <ceres/ceres.h>
#endif
#ifdef SWBA_BENCH_HAVE_MRPT_GRAPHSLAM
#include <mrpt/graphs/CNetworkOfPoses.h>
#include <mrpt/graphslam/levmarq.h>
#include <mrpt/poses/CPose3DQuat.h>
#endif

namespace
{
using swba::io::PoseGraph;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

struct Settings
{
	int threads = 2;
	int max_iterations = 100;
	int repeat = 1;
	int mrpt_max_iterations = 100;
	double initial_trust_region = swba::io::kPoseGraphInitialTrustRegion;  // swba's rows and the ceres:tr row
	bool run_ceres_tr = true;
	bool run_ceres = true;
	bool run_mrpt = true;
	std::vector<swba::RotationError> models = {swba::RotationError::G2o, swba::RotationError::CeresExample};
	/** swba rows: (method, solve positions — chordal only: false = chordal rotations + odometry positions). */
	std::vector<std::pair<swba::io::PoseGraphInit, bool>> inits = {{swba::io::PoseGraphInit::Chordal, true},
																   {swba::io::PoseGraphInit::Odometry, true}};
	std::vector<std::string> graphs;
};

struct Result
{
	std::string solver;
	double final_cost = -1;  // pose_graph_cost of the solver's output
	double reported_cost = -1;  // what the solver itself reports (its own definition)
	int iterations = 0;
	double setup_s = 0, solve_s = 0;
	double init_s = 0;          // initialisation, included in solve_s
	double start_cost = -1;     // pose_graph_cost where the solver starts (after the initialisation)
	std::string note;
	PoseGraph solution;  // the solver's output (for re-evaluation under another model)
};

const char* model_name(swba::RotationError m) { return m == swba::RotationError::G2o ? "g2o" : "ceres"; }

// ---------------------------------------------------------------- swba
Result run_swba(const PoseGraph& input, const Settings& s, swba::RotationError model, swba::io::PoseGraphInit init,
				bool solve_positions)
{
	Result r;
	r.solver = "swba:" + swba::io::to_string(init).substr(0, 4) + (solve_positions ? "" : "-r");
	for (int rep = 0; rep < s.repeat; rep++)
	{
		PoseGraph g = input;
		// The initialisation is timed as part of the solve (it replaces LM iterations).
		auto t0 = Clock::now();
		swba::io::PoseGraphInitOptions init_options;
		init_options.method = init;
		init_options.solve_positions = solve_positions;
		init_options.rotation_error = model;
		const auto init_summary = swba::io::initialize_pose_graph(g, init_options);
		const double init_s = seconds_since(t0);
		const double start_cost = swba::io::pose_graph_cost(g, model);
		t0 = Clock::now();
		swba::io::PoseGraphProblemOptions po;
		po.rotation_error = model;
		auto pp = swba::io::build_pose_graph_problem(g, po);
		const double setup = seconds_since(t0);
		swba::SolverOptions o = swba::io::pose_graph_solver_options();  // as swba pgo
		o.max_iterations = s.max_iterations;
		o.num_threads = s.threads;
		o.initial_trust_region_radius = s.initial_trust_region;
		t0 = Clock::now();
		const auto summary = swba::solve(pp.problem, o);
		const double solve = init_s + seconds_since(t0);
		swba::io::update_pose_graph(g, pp);
		if (rep == 0 || solve < r.solve_s)
		{
			r.setup_s = setup;
			r.solve_s = solve;
			r.init_s = init_s;
		}
		r.start_cost = start_cost;
		r.final_cost = swba::io::pose_graph_cost(g, model);
		r.reported_cost = summary.final_cost;
		r.iterations = summary.iterations;
		r.note = init_summary.brief() + "; " + summary.brief_report();
		r.solution = g;
	}
	return r;
}

// ---------------------------------------------------------------- Ceres
#ifdef SWBA_BENCH_HAVE_CERES
/** Reference 3D model: r = Lᵀ·[R_aᵀ(t_b − t_a) − t_ab ; 2·vec(δq)], Λ = L·Lᵀ, with
 * δq = q_ab⁻¹·q_a⁻¹·q_b (g2o) or q_ab·(q_a⁻¹·q_b)⁻¹ (Ceres's pose_graph_3d example). */
struct ReferencePose3dCost
{
	ReferencePose3dCost(const swba::io::PoseGraphEdge3& e, swba::RotationError model)
		: t_ab(e.t), q_ab(e.q), g2o(model == swba::RotationError::G2o)
	{
		W = e.information.llt().matrixL().transpose();
	}
	template <typename T>
	bool operator()(const T* pa, const T* qa, const T* pb, const T* qb, T* residual) const
	{
		const Eigen::Map<const Eigen::Matrix<T, 3, 1>> p_a(pa), p_b(pb);
		const Eigen::Map<const Eigen::Quaternion<T>> q_a(qa), q_b(qb);
		const Eigen::Quaternion<T> q_a_inv = q_a.conjugate();
		const Eigen::Quaternion<T> q_est = q_a_inv * q_b;
		const Eigen::Quaternion<T> dq = g2o ? Eigen::Quaternion<T>(q_ab.conjugate().template cast<T>() * q_est)
											: Eigen::Quaternion<T>(q_ab.template cast<T>() * q_est.conjugate());
		Eigen::Map<Eigen::Matrix<T, 6, 1>> r(residual);
		r.template head<3>() = q_a_inv * (p_b - p_a) - t_ab.template cast<T>();
		r.template tail<3>() = T(2.0) * dq.vec();
		r.applyOnTheLeft(W.template cast<T>());
		return true;
	}
	Eigen::Vector3d t_ab;
	Eigen::Quaterniond q_ab;
	bool g2o;
	Eigen::Matrix<double, 6, 6> W;
	EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

template <typename T>
T normalize_angle(const T& a)
{
	const T two_pi(2.0 * M_PI);
	return a - two_pi * ceres::floor((a + T(M_PI)) / two_pi);
}

/** Reference 2D model: r = Lᵀ·[R(θ_a)ᵀ(p_b − p_a) − p_ab ; wrap(θ_b − θ_a − θ_ab)]. */
struct ReferencePose2dCost
{
	explicit ReferencePose2dCost(const swba::io::PoseGraphEdge2& e) : x(e.x), y(e.y), theta(e.theta)
	{
		W = e.information.llt().matrixL().transpose();
	}
	template <typename T>
	bool operator()(const T* a, const T* b, T* residual) const
	{
		const T c = ceres::cos(a[2]), s = ceres::sin(a[2]);
		const T dx = b[0] - a[0], dy = b[1] - a[1];
		Eigen::Matrix<T, 3, 1> r(c * dx + s * dy - T(x), -s * dx + c * dy - T(y),
								 normalize_angle(b[2] - a[2] - T(theta)));
		Eigen::Map<Eigen::Matrix<T, 3, 1>> out(residual);
		out = W.template cast<T>() * r;
		return true;
	}
	double x, y, theta;
	Eigen::Matrix3d W;
};

/** Ceres with its default options, or (`initial_trust_region` > 0) with that initial radius. */
Result run_ceres(const PoseGraph& input, const Settings& s, swba::RotationError model, double initial_trust_region)
{
	Result res;
	res.solver = initial_trust_region > 0 ? "ceres:tr" : "ceres";
	for (int rep = 0; rep < s.repeat; rep++)
	{
		PoseGraph g = input;
		auto t0 = Clock::now();
		ceres::Problem problem;
		// Parameter storage: 3D p(3) + q(4, Eigen order x y z w); 2D (x, y, θ).
		std::map<swba::io::G2oId, std::array<double, 7>> params;
		for (const auto& [id, v] : g.vertices3)
		{
			auto& p = params[id];
			for (int i = 0; i < 3; i++) p[i] = v.t[i];
			for (int i = 0; i < 4; i++) p[3 + i] = v.q.coeffs()[i];
		}
		for (const auto& [id, v] : g.vertices2) params[id] = {v.x, v.y, v.theta, 0, 0, 0, 0};
		for (const auto& e : g.edges3)
		{
			double* a = params.at(e.from).data();
			double* b = params.at(e.to).data();
			problem.AddResidualBlock(new ceres::AutoDiffCostFunction<ReferencePose3dCost, 6, 3, 4, 3, 4>(
										 new ReferencePose3dCost(e, model)),
									 nullptr, a, a + 3, b, b + 3);
		}
		for (const auto& e : g.edges2)
			problem.AddResidualBlock(
				new ceres::AutoDiffCostFunction<ReferencePose2dCost, 3, 3, 3>(new ReferencePose2dCost(e)), nullptr,
				params.at(e.from).data(), params.at(e.to).data());
		auto* quaternion_manifold = new ceres::EigenQuaternionManifold;  // owned by the problem
		bool manifold_used = false;
		for (auto& [id, p] : params)
		{
			if (!g.is_2d() && problem.HasParameterBlock(p.data() + 3))
			{
				problem.SetManifold(p.data() + 3, quaternion_manifold);
				manifold_used = true;
			}
		}
		if (!manifold_used) delete quaternion_manifold;
		// Gauge: FIX lines, else the lowest id (as swba's default).
		std::set<swba::io::G2oId> fixed = g.fixed;
		if (fixed.empty()) fixed.insert(params.begin()->first);
		for (auto id : fixed)
		{
			double* p = params.at(id).data();
			if (problem.HasParameterBlock(p)) problem.SetParameterBlockConstant(p);
			if (!g.is_2d() && problem.HasParameterBlock(p + 3)) problem.SetParameterBlockConstant(p + 3);
		}
		const double setup = seconds_since(t0);

		ceres::Solver::Options o;
		o.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
		o.max_num_iterations = s.max_iterations;
		o.num_threads = s.threads;
		o.minimizer_progress_to_stdout = false;
		if (initial_trust_region > 0)
		{
			o.initial_trust_region_radius = initial_trust_region;
			o.max_trust_region_radius = std::max(o.max_trust_region_radius, initial_trust_region);
		}
		ceres::Solver::Summary summary;
		t0 = Clock::now();
		ceres::Solve(o, &problem, &summary);
		const double solve = seconds_since(t0);

		for (auto& [id, v] : g.vertices3)
		{
			const auto& p = params.at(id);
			v.t = Eigen::Vector3d(p[0], p[1], p[2]);
			v.q = Eigen::Quaterniond(p[6], p[3], p[4], p[5]).normalized();
		}
		for (auto& [id, v] : g.vertices2)
		{
			const auto& p = params.at(id);
			v = {p[0], p[1], p[2]};
		}
		if (rep == 0 || solve < res.solve_s)
		{
			res.setup_s = setup;
			res.solve_s = solve;
		}
		res.final_cost = swba::io::pose_graph_cost(g, model);
		res.reported_cost = summary.final_cost;
		res.iterations = static_cast<int>(summary.iterations.size()) - 1;  // iteration 0 is the start
		res.note = summary.BriefReport();
		res.solution = g;
	}
	return res;
}
#endif

// ---------------------------------------------------------------- MRPT
#ifdef SWBA_BENCH_HAVE_MRPT_GRAPHSLAM
Result run_mrpt(const PoseGraph& input, const Settings& s)
{
	Result res;
	res.solver = "mrpt";
	PoseGraph g = input;
	try
	{
		mrpt::graphslam::TResultInfoSpaLevMarq info;
		mrpt::containers::yaml params;
		params["max_iterations"] = s.mrpt_max_iterations;
		const auto first = g.is_2d() ? g.vertices2.begin()->first : g.vertices3.begin()->first;
		if (!g.is_2d())
		{
			auto t0 = Clock::now();
			mrpt::graphs::CNetworkOfPoses3DInf G;
			const auto to_pose = [](const Eigen::Vector3d& t, const Eigen::Quaterniond& q) {
				return mrpt::poses::CPose3D(mrpt::poses::CPose3DQuat(
					t.x(), t.y(), t.z(), mrpt::math::CQuaternionDouble(q.w(), q.x(), q.y(), q.z())));
			};
			for (const auto& [id, v] : g.vertices3) G.nodes[static_cast<mrpt::graphs::TNodeID>(id)] = to_pose(v.t, v.q);
			for (const auto& e : g.edges3)
			{
				mrpt::poses::CPose3DPDFGaussianInf pdf;
				pdf.mean = to_pose(e.t, e.q);
				// MRPT's levmarq whitens the pseudo-log [t; ω] with cov_inv as is, so the g2o information,
				// ordered (x, y, z, qx, qy, qz) ≈ (t, ω), is passed unpermuted.
				pdf.cov_inv.asEigen() = e.information;
				G.insertEdge(static_cast<mrpt::graphs::TNodeID>(e.from), static_cast<mrpt::graphs::TNodeID>(e.to), pdf);
			}
			G.root = static_cast<mrpt::graphs::TNodeID>(first);
			res.setup_s = seconds_since(t0);
			t0 = Clock::now();
			mrpt::graphslam::optimize_graph_spa_levmarq(G, info, nullptr, params);
			res.solve_s = seconds_since(t0);
			for (auto& [id, v] : g.vertices3)
			{
				const auto& P = G.nodes.at(static_cast<mrpt::graphs::TNodeID>(id));
				v.t = Eigen::Vector3d(P.x(), P.y(), P.z());
				v.q = Eigen::Quaterniond(Eigen::Matrix3d(P.getRotationMatrix().asEigen())).normalized();
			}
		}
		else
		{
			auto t0 = Clock::now();
			mrpt::graphs::CNetworkOfPoses2DInf G;
			for (const auto& [id, v] : g.vertices2)
				G.nodes[static_cast<mrpt::graphs::TNodeID>(id)] = mrpt::poses::CPose2D(v.x, v.y, v.theta);
			for (const auto& e : g.edges2)
			{
				mrpt::poses::CPosePDFGaussianInf pdf;
				pdf.mean = mrpt::poses::CPose2D(e.x, e.y, e.theta);
				pdf.cov_inv.asEigen() = e.information;
				G.insertEdge(static_cast<mrpt::graphs::TNodeID>(e.from), static_cast<mrpt::graphs::TNodeID>(e.to), pdf);
			}
			G.root = static_cast<mrpt::graphs::TNodeID>(first);
			res.setup_s = seconds_since(t0);
			t0 = Clock::now();
			mrpt::graphslam::optimize_graph_spa_levmarq(G, info, nullptr, params);
			res.solve_s = seconds_since(t0);
			for (auto& [id, v] : g.vertices2)
			{
				const auto& P = G.nodes.at(static_cast<mrpt::graphs::TNodeID>(id));
				v = {P.x(), P.y(), P.phi()};
			}
		}
		res.iterations = static_cast<int>(info.num_iters);
		res.reported_cost = info.final_total_sq_error;
		res.final_cost = 0;  // evaluated per model by the caller
		res.solution = g;
		res.note = "solver's cost = MRPT's own unweighted sum of squared errors";
	}
	catch (const std::exception& e)
	{
		std::string what = e.what();
		std::replace(what.begin(), what.end(), '\n', ' ');
		res.note = "FAILED: " + what.substr(0, 200);
	}
	return res;
}
#endif

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
}  // namespace

int main(int argc, char** argv)
{
	Settings s;
	const char* usage =
		"usage: swba_bench_pgo [--threads N] [--max-iterations K] [--repeat R] [--mrpt-max-iterations K]\n"
		"                      [--model g2o|ceres|both] [--init LIST] [--initial-trust-region MU0] [--no-ceres-tr]\n"
		"                      [--no-mrpt] [--no-ceres] [graph.g2o ...]\n"
		"  --init: comma-separated swba initialisations among chordal, odometry, file, chordal-rot (chordal rotations,\n"
		"          positions composed along the odometry tree) (default chordal,odometry)\n"
		"  --initial-trust-region: swba's initial LM radius (default 1e12, as swba pgo), also used by the ceres:tr row\n"
		"  --no-ceres-tr: omit the ceres:tr row (Ceres from the file with swba's initial radius)\n";
	for (int i = 1; i < argc; i++)
	{
		const std::string a = argv[i];
		const auto next = [&]() -> const char* {
			if (i + 1 >= argc)
			{
				std::fprintf(stderr, "swba_bench_pgo: %s needs a value\n", a.c_str());
				std::exit(2);
			}
			return argv[++i];
		};
		if (a == "--threads") s.threads = parse_int(next(), "--threads");
		else if (a == "--max-iterations") s.max_iterations = parse_int(next(), "--max-iterations");
		else if (a == "--repeat") s.repeat = parse_int(next(), "--repeat");
		else if (a == "--mrpt-max-iterations") s.mrpt_max_iterations = parse_int(next(), "--mrpt-max-iterations");
		else if (a == "--model")
		{
			const std::string m = next();
			if (m == "both") s.models = {swba::RotationError::G2o, swba::RotationError::CeresExample};
			else if (m == "g2o" || m == "ceres") s.models = {swba::io::parse_rotation_error(m)};
			else
			{
				std::fprintf(stderr, "swba_bench_pgo: --model expects g2o, ceres or both\n");
				return 2;
			}
		}
		else if (a == "--init")
		{
			s.inits.clear();
			std::string list = next();
			for (size_t pos = 0; pos <= list.size();)
			{
				const size_t comma = std::min(list.find(',', pos), list.size());
				try
				{
					const std::string name = list.substr(pos, comma - pos);
					if (name == "chordal-rot") s.inits.emplace_back(swba::io::PoseGraphInit::Chordal, false);
					else s.inits.emplace_back(swba::io::parse_pose_graph_init(name), true);
				}
				catch (const std::invalid_argument& e)
				{
					std::fprintf(stderr, "swba_bench_pgo: --init: %s\n", e.what());
					return 2;
				}
				pos = comma + 1;
			}
		}
		else if (a == "--initial-trust-region")
		{
			s.initial_trust_region = std::atof(next());
			if (!(s.initial_trust_region > 0))
			{
				std::fprintf(stderr, "swba_bench_pgo: --initial-trust-region needs a positive number\n");
				return 2;
			}
		}
		else if (a == "--no-ceres-tr") s.run_ceres_tr = false;
		else if (a == "--no-mrpt") s.run_mrpt = false;
		else if (a == "--no-ceres") s.run_ceres = false;
		else if (a == "--help" || a == "-h")
		{
			std::printf("%s", usage);
			return 0;
		}
		else if (!a.empty() && a[0] == '-')
		{
			std::fprintf(stderr, "swba_bench_pgo: unknown option %s\n%s", a.c_str(), usage);
			return 2;
		}
		else s.graphs.push_back(a);
	}
	if (s.graphs.empty())
		for (const char* n : {"sphere2500", "parking-garage", "smallGrid3D", "intel"})
			s.graphs.push_back(std::string(SWBA_DATA_DIR) + "/posegraph/" + n + ".g2o");

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
	int rc = 0;
	for (const auto& path : s.graphs)
	{
		PoseGraph g;
		try
		{
			g = swba::io::read_g2o(path);
		}
		catch (const std::exception& e)
		{
			std::fprintf(stderr, "%s\n", e.what());
			rc = 1;
			continue;
		}
		std::string name = path.substr(path.find_last_of('/') + 1);
		if (name.size() > 4 && name.substr(name.size() - 4) == ".g2o") name.resize(name.size() - 4);
		std::vector<swba::RotationError> models = s.models;
		if (g.is_2d()) models = {swba::RotationError::G2o};  // the rotation convention is 3D only

		std::vector<std::string> notes;
		Result mrpt;
#ifdef SWBA_BENCH_HAVE_MRPT_GRAPHSLAM
		if (s.run_mrpt) mrpt = run_mrpt(g, s);
#endif
		for (const auto model : models)
		{
			const char* mname = g.is_2d() ? "2d" : model_name(model);
			const double initial = swba::io::pose_graph_cost(g, model);
			std::vector<Result> results;
			for (const auto& [init, positions] : s.inits) results.push_back(run_swba(g, s, model, init, positions));
#ifdef SWBA_BENCH_HAVE_CERES
			if (s.run_ceres) results.push_back(run_ceres(g, s, model, -1));
			if (s.run_ceres && s.run_ceres_tr) results.push_back(run_ceres(g, s, model, s.initial_trust_region));
#endif
			if (!mrpt.solver.empty())
			{
				results.push_back(mrpt);
				if (mrpt.final_cost >= 0) results.back().final_cost = swba::io::pose_graph_cost(mrpt.solution, model);
			}
			const Result* ceres = nullptr;
			const Result* ceres_tr = nullptr;
			for (const auto& r : results)
			{
				if (r.solver == "ceres") ceres = &r;
				if (r.solver == "ceres:tr") ceres_tr = &r;
			}
			for (const auto& r : results)
			{
				char ratio[32] = "", ratio_tr[32] = "";
				const bool ours = r.solver.rfind("swba", 0) == 0;
				if (ceres && ours && ceres->solve_s > 0)
					std::snprintf(ratio, sizeof ratio, "%.2f", r.solve_s / ceres->solve_s);
				if (ceres_tr && ours && ceres_tr->solve_s > 0)
					std::snprintf(ratio_tr, sizeof ratio_tr, "%.2f", r.solve_s / ceres_tr->solve_s);
				const double start = r.start_cost >= 0 ? r.start_cost : initial;
				char init_s[16] = "-";
				if (ours) std::snprintf(init_s, sizeof init_s, "%.3f", r.init_s);
				if (r.final_cost < 0)
					std::printf("%-15s %-5s %-9s %13.6e %16s %16s %5s %8s %8s %8s %10s  %s\n", name.c_str(), mname,
								r.solver.c_str(), start, "-", "-", "-", "-", "-", "-", "", r.note.c_str());
				else
					std::printf("%-15s %-5s %-9s %13.6e %16.10g %16.10g %5d %8.3f %8s %8.3f %10s %9s\n", name.c_str(),
								mname, r.solver.c_str(), start, r.final_cost, r.reported_cost, r.iterations, r.setup_s,
								init_s, r.solve_s, ratio, ratio_tr);
				if (!r.note.empty() && r.final_cost >= 0)
					notes.push_back(name + " " + mname + " " + r.solver + ": " + r.note);
			}
			if (ceres && ceres->final_cost > 0)
				for (const auto& r : results)
					if (r.solver.rfind("swba", 0) == 0)
					{
						char buf[64];
						std::snprintf(buf, sizeof buf, "%+.2e", (r.final_cost - ceres->final_cost) / ceres->final_cost);
						notes.push_back(name + " " + mname + ": relative final-cost difference " + r.solver + " vs ceres " +
										buf);
					}
			std::fflush(stdout);
		}
		for (const auto& n : notes) std::printf("    %s\n", n.c_str());
	}
	return rc;
}
