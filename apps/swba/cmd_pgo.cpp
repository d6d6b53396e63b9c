// swba pgo: pose-graph optimisation of a g2o file (3D VERTEX_SE3:QUAT/EDGE_SE3:QUAT or 2D SE2).
#include <swba/io/g2o.h>
#include <swba/io/g2o_init.h>
#include <swba/nonlinear/solver.h>

#include <iostream>

#include "cli.h"
#include "command.h"

namespace
{
using swba::io::kPoseGraphInitialTrustRegion;

int run_pgo(int argc, char** argv)
{
	TCLAP::CmdLine cmd(
		"Optimises a g2o pose graph (VERTEX_SE3:QUAT/EDGE_SE3:QUAT or VERTEX_SE2/EDGE_SE2, FIX) with "
		"Levenberg-Marquardt and writes the optimised graph. Cost = 1/2 sum r^T Lambda r (see doc/pgo.md).",
		' ', "0.1.0");
	TCLAP::UnlabeledValueArg<std::string> input("input", "input g2o file", true, "", "IN.g2o", cmd);
	TCLAP::ValueArg<std::string> output("o", "output", "write the optimised graph here (default: not written)",
										false, "", "OUT.g2o", cmd);
	TCLAP::ValueArg<int> max_iterations("", "max-iterations", "maximum LM iterations (default 100)", false,
										100, "K", cmd);
	TCLAP::ValueArg<std::string> robust("", "robust", "robust loss: none, huber or cauchy (default none)",
										false, "none", "none|huber|cauchy", cmd);
	TCLAP::ValueArg<double> robust_scale("", "robust-scale",
										 "loss scale in whitened residual units (default 1)", false, 1.0, "S", cmd);
	TCLAP::ValueArg<int> threads("", "threads", "threads for evaluation and assembly (default 1)", false, 1,
								 "N", cmd);
	TCLAP::ValueArg<std::string> linear(
		"", "linear", "linear solver: auto, dense-normal, sparse-normal (default auto)", false, "auto",
		"auto|dense-normal|sparse-normal", cmd);
	TCLAP::ValueArg<std::string> gauge(
		"", "gauge",
		"fix: FIX lines, else the lowest-id vertex held constant; prior: FIX lines, else a prior of "
		"sigma --prior-sigma on the lowest-id vertex; free: FIX lines only (default fix)",
		false, "fix", "fix|prior|free", cmd);
	TCLAP::ValueArg<double> prior_sigma("", "prior-sigma", "gauge prior sigma in m and rad (default 1e-3)",
										false, 1e-3, "SIGMA", cmd);
	TCLAP::ValueArg<double> function_tolerance(
		"", "function-tolerance", "stop when |dcost|/cost falls below (default 1e-6)", false, 1e-6, "TOL", cmd);
	TCLAP::ValueArg<double> initial_radius(
		"", "initial-trust-region", "initial LM trust-region radius mu0, damping 1/mu0 (default 1e12; Ceres uses 1e4)",
		false, kPoseGraphInitialTrustRegion, "MU0", cmd);
	TCLAP::ValueArg<std::string> rotation_error(
		"", "rotation-error",
		"3D rotation error: g2o = 2 vec(q_ab^-1 q_a^-1 q_b), ceres = 2 vec(q_ab (q_a^-1 q_b)^-1) as Ceres's "
		"pose_graph_3d example (default g2o)",
		false, "g2o", "g2o|ceres", cmd);
	TCLAP::ValueArg<std::string> init(
		"", "init",
		"initial values: chordal = chordal-relaxation rotations, then positions by linear least squares; "
		"odometry = poses composed along the odometry spanning tree; file = the values as read (default chordal)",
		false, "chordal", "chordal|odometry|file", cmd);
	TCLAP::SwitchArg quiet("q", "quiet", "do not print the per-iteration table", cmd);
	if (auto rc = swba::app::parse_command_line(cmd, argc, argv)) return *rc;

	swba::io::PoseGraphProblemOptions po;
	swba::io::PoseGraphInitOptions init_options;
	swba::SolverOptions so = swba::io::pose_graph_solver_options();
	try
	{
		init_options.method = swba::io::parse_pose_graph_init(init.getValue());
		po.gauge = swba::io::parse_pose_graph_gauge(gauge.getValue());
		po.prior_sigma = prior_sigma.getValue();
		po.rotation_error = swba::io::parse_rotation_error(rotation_error.getValue());
		if (!(po.prior_sigma > 0)) throw std::invalid_argument("--prior-sigma must be > 0");
		if (!(robust_scale.getValue() > 0)) throw std::invalid_argument("--robust-scale must be > 0");
		po.loss = swba::make_loss(robust.getValue(), robust_scale.getValue());
		so.linear_solver = swba::parse_linear_solver(linear.getValue());
		if (so.linear_solver == swba::LinearSolverType::DenseSchur ||
			so.linear_solver == swba::LinearSolverType::SparseSchur)
			throw std::invalid_argument("--linear " + linear.getValue() +
										": a pose graph has no variables to eliminate (use auto, dense-normal "
										"or sparse-normal)");
	}
	catch (const std::invalid_argument& e)
	{
		throw swba::app::UsageError(e.what());
	}
	// pose_graph_solver_options(): dense LDLT only up to 200 unknowns — pose-graph normal equations are very
	// sparse (≈ 4 6×6 blocks per block row; smallGrid3D, 744 unknowns: 0.09 s sparse vs 0.70 s dense).
	so.max_iterations = max_iterations.getValue();
	so.num_threads = threads.getValue();
	so.function_tolerance = function_tolerance.getValue();
	so.initial_trust_region_radius = initial_radius.getValue();
	so.progress_to_stdout = !quiet.getValue();
	if (std::string why; !so.is_valid(&why)) throw swba::app::UsageError(why);

	swba::io::PoseGraph graph = swba::io::read_g2o(input.getValue());
	if (const auto skipped = graph.skipped_summary(); !skipped.empty())
		std::cerr << "swba pgo: warning: " << skipped << "\n";
	std::cout << "Pose graph " << input.getValue() << ": " << graph.num_vertices() << " vertices, "
			  << graph.num_edges() << " edges (" << (graph.is_2d() ? "2D SE2" : "3D SE3:QUAT") << "), "
			  << graph.fixed.size() << " FIX\n";
	init_options.rotation_error = po.rotation_error;
	const auto init_summary = swba::io::initialize_pose_graph(graph, init_options);
	std::cout << "Initialisation " << init_summary.brief() << "\n";
	auto pp = swba::io::build_pose_graph_problem(graph, po);
	std::cout << "Gauge: " << gauge.getValue() << " (" << pp.num_constant << " constant vertices"
			  << (pp.has_prior ? ", prior on the first vertex" : "") << ")\n";

	const swba::Summary summary = swba::solve(pp.problem, so);
	std::cout << summary.full_report();
	swba::io::update_pose_graph(graph, pp);
	if (po.loss || pp.has_prior)
		std::cout << "Edge cost without loss/prior: " << swba::io::pose_graph_cost(graph, po.rotation_error) << "\n";
	if (!summary.is_solution_usable())
		throw std::runtime_error("optimisation failed: " + summary.message);
	if (!output.getValue().empty())
	{
		swba::io::write_g2o(graph, output.getValue());
		std::cout << "Wrote " << output.getValue() << "\n";
	}
	return 0;
}
SWBA_REGISTER_COMMAND("pgo", "optimise a g2o pose graph (3D or 2D)", run_pgo);
}  // namespace
