// swba pgo: pose-graph optimisation of a g2o file (3D VERTEX_SE3:QUAT/EDGE_SE3:QUAT or 2D SE2).
// Logic in swba/apps/pgo.h.
#include <swba/apps/pgo.h>

#include <cstdio>
#include <iostream>
#include <stdexcept>
#include <string>

#include "cli.h"
#include "command.h"

namespace
{
struct PgoCommandLine
{
	TCLAP::CmdLine cmd{
		"Optimises a g2o pose graph (VERTEX_SE3:QUAT/EDGE_SE3:QUAT or VERTEX_SE2/EDGE_SE2, FIX) with "
		"Levenberg-Marquardt and writes the optimised graph. Cost = 1/2 sum r^T Lambda r (see doc/pgo.md).",
		' ', "0.1.0"};
	TCLAP::UnlabeledValueArg<std::string> input{"IN.g2o", "input g2o file", true, "", "IN.g2o", cmd};
	TCLAP::ValueArg<std::string> information{
		"", "information",
		"edge information matrices that are not positive definite: strict = error naming file:line; repair = "
		"replace each by the nearest positive-definite matrix (symmetrise, clip eigenvalues below 1e-6 x the "
		"largest), counted on stderr and in the report (Default: strict)",
		false, "strict", swba::enum_choices<swba::io::InformationPolicy>("|"), cmd};
	TCLAP::ValueArg<std::string> init{
		"", "init",
		"initial values: chordal = chordal-relaxation rotations, then positions by linear least squares; "
		"odometry = poses composed along the odometry spanning tree; file = the values as read (Default: chordal)",
		false, "chordal", "chordal|odometry|file", cmd};
	TCLAP::ValueArg<std::string> gauge{
		"", "gauge",
		"fixed: FIX lines, else the lowest-id vertex held constant (\"fix\" is accepted too); prior: FIX lines, "
		"else a prior of sigma --prior-sigma on the lowest-id vertex; free: FIX lines only (Default: fixed)",
		false, "fixed", "fixed|prior|free", cmd};
	TCLAP::ValueArg<double> prior_sigma{
		"", "prior-sigma", "gauge prior sigma in m and rad (Default: 1e-3)", false, 1e-3, "SIGMA", cmd};
	TCLAP::ValueArg<std::string> robust{
		"", "robust", "robust loss: none, huber or cauchy (Default: none)", false, "none", "none|huber|cauchy", cmd};
	TCLAP::ValueArg<double> robust_scale{
		"", "robust-scale", "loss scale in whitened residual units (Default: 1)", false, 1.0, "S", cmd};
	TCLAP::ValueArg<std::string> rotation_error{
		"", "rotation-error",
		"3D rotation error: g2o = 2 vec(q_ab^-1 q_a^-1 q_b), ceres = 2 vec(q_ab (q_a^-1 q_b)^-1) as Ceres's "
		"pose_graph_3d example (Default: g2o)",
		false, "g2o", "g2o|ceres", cmd};
	TCLAP::ValueArg<std::string> linear{"",
										"linear",
										"linear solver: auto, dense-normal, sparse-normal (Default: auto)",
										false,
										"auto",
										"auto|dense-normal|sparse-normal",
										cmd};
	TCLAP::ValueArg<int> max_iterations =
		swba::app::max_iterations_arg(cmd, swba::problems::pose_graph_solver_options().max_iterations);
	TCLAP::ValueArg<double> function_tolerance{
		"", "function-tolerance", "stop when |dcost|/cost falls below (Default: 1e-6)", false, 1e-6, "TOL", cmd};
	TCLAP::ValueArg<double> initial_radius{
		"", "initial-trust-region", "initial LM trust-region radius mu0, damping 1/mu0 (Default: 1e12; Ceres uses 1e4)",
		false, swba::problems::kPoseGraphInitialTrustRegion, "MU0", cmd};
	TCLAP::ValueArg<int> threads = swba::app::threads_arg(cmd);
	TCLAP::ValueArg<std::string> output{
		"o", "output", "write the optimised graph here (Default: not written)", false, "", "OUT.g2o", cmd};
	TCLAP::SwitchArg quiet = swba::app::quiet_arg(cmd);
};

/** The typed options; the checks name the flags (bad values are usage errors). */
swba::apps::PgoAppOptions options_from(PgoCommandLine& a)
{
	swba::apps::PgoAppOptions o;
	o.input_path = a.input.getValue();
	o.output_path = a.output.getValue();
	try
	{
		o.init = swba::problems::parse_pose_graph_init(a.init.getValue());
		o.read.information = swba::parse_enum<swba::io::InformationPolicy>(a.information.getValue(), "information policy");
		o.gauge = swba::problems::parse_pose_graph_gauge(a.gauge.getValue());
		o.prior_sigma = a.prior_sigma.getValue();
		o.rotation_error = swba::problems::parse_rotation_error(a.rotation_error.getValue());
		if (!(o.prior_sigma > 0)) throw std::invalid_argument("--prior-sigma must be > 0");
		if (!(a.robust_scale.getValue() > 0)) throw std::invalid_argument("--robust-scale must be > 0");
		o.loss = swba::parse_enum<swba::RobustLoss>(a.robust.getValue(), "loss");
		o.loss_scale = a.robust_scale.getValue();
		o.solver.linear_solver = swba::parse_linear_solver(a.linear.getValue());
		if (o.solver.linear_solver == swba::LinearSolverType::DenseSchur ||
			o.solver.linear_solver == swba::LinearSolverType::SparseSchur)
			throw std::invalid_argument("--linear " + a.linear.getValue() +
										": a pose graph has no variables to eliminate (use auto, dense-normal "
										"or sparse-normal)");
		o.solver.max_iterations = a.max_iterations.getValue();
		o.solver.num_threads = a.threads.getValue();
		o.solver.function_tolerance = a.function_tolerance.getValue();
		o.solver.initial_trust_region_radius = a.initial_radius.getValue();
		if (o.solver.max_iterations < 0) throw std::invalid_argument("--max-iterations must be >= 0");
		if (o.solver.num_threads < 1) throw std::invalid_argument("--threads must be >= 1");
		if (!(o.solver.function_tolerance >= 0)) throw std::invalid_argument("--function-tolerance must be >= 0");
		const double max_radius = o.solver.max_trust_region_radius;
		if (!(o.solver.initial_trust_region_radius > 0 && o.solver.initial_trust_region_radius <= max_radius))
		{
			char buf[32];
			std::snprintf(buf, sizeof buf, "%g", max_radius);
			throw std::invalid_argument(std::string("--initial-trust-region must be in (0, ") + buf +
										"] (the maximum trust-region radius)");
		}
	}
	catch (const std::invalid_argument& e)
	{
		throw swba::app::UsageError(e.what());
	}
	o.solver.progress_to_stdout = !a.quiet.getValue();
	swba::app::validate_usage(o);
	return o;
}

SWBA_REGISTER_COMMAND("pgo", "optimise a g2o pose graph (3D or 2D)",
					  swba::app::app_command<PgoCommandLine>(swba::apps::run_pgo_app));
}  // namespace
