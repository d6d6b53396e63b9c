// swba bal: bundle adjustment of a BAL problem (Snavely cameras) with swba's LM and Schur elimination.
// Logic in swba/apps/bal.h.
#include <swba/apps/bal.h>

#include <iostream>
#include <stdexcept>

#include "cli.h"
#include "command.h"

namespace
{
struct BalCommandLine
{
	TCLAP::CmdLine cmd{
		"Bundle adjustment of a BAL problem ('Bundle Adjustment in the Large'): Snavely cameras, points eliminated "
		"by a Schur complement, Levenberg-Marquardt. Prints the per-iteration table and a summary.",
		' ', "0.1.0"};
	TCLAP::UnlabeledValueArg<std::string> problem{
		"PROBLEM", "BAL problem file (plain text, or bzip2 if supported)", true, "", "PROBLEM", cmd};
	TCLAP::ValueArg<std::string> linear{"", "linear",
										"reduced camera system: dense-schur, sparse-schur (CHOLMOD) or auto = dense up to 1500 unknowns "
										"(Default: auto)",
										false, "auto", "dense-schur|sparse-schur|auto", cmd};
	TCLAP::ValueArg<std::string> loss{
		"", "loss", "robust loss: none, huber or cauchy (Default: none)", false, "none", "none|huber|cauchy", cmd};
	TCLAP::ValueArg<double> loss_scale{"", "loss-scale", "loss scale in pixels (Default: 1)", false, 1.0, "S", cmd};
	TCLAP::ValueArg<int> max_iterations{"", "max-iterations", "LM iteration limit (Default: 50)", false, 50, "K", cmd};
	TCLAP::ValueArg<double> ftol{
		"", "function-tolerance", "stop when |Δcost|/cost < this (Default: 1e-6)", false, 1e-6, "TOL", cmd};
	TCLAP::ValueArg<double> gtol{
		"", "gradient-tolerance", "stop when max|gradient| ≤ this (Default: 1e-10)", false, 1e-10, "TOL", cmd};
	TCLAP::ValueArg<double> ptol{
		"", "parameter-tolerance", "stop when |step| ≤ this·(|x| + this) (Default: 1e-8)", false, 1e-8, "TOL", cmd};
	TCLAP::ValueArg<int> threads{"", "threads", "threads for evaluation and Schur assembly (Default: 2)", false, 2, "N", cmd};
	TCLAP::ValueArg<std::string> ply_initial{
		"", "ply-initial", "write the initial cameras (green) and points (white) as PLY (Default: not written)", false, "", "FILE", cmd};
	TCLAP::ValueArg<std::string> ply_final{"", "ply-final", "write the solution as PLY (Default: not written)", false, "", "FILE", cmd};
	TCLAP::ValueArg<std::string> write_problem{
		"", "write-problem", "write the solution in the BAL format (Default: not written)", false, "", "OUT", cmd};
	TCLAP::SwitchArg quiet = swba::app::quiet_arg(cmd);
};

/** The typed options; the checks name the flags (bad values are usage errors). */
swba::apps::BalAppOptions options_from(BalCommandLine& a)
{
	using swba::app::UsageError;
	swba::apps::BalAppOptions o;
	o.problem_path = a.problem.getValue();
	o.ply_initial = a.ply_initial.getValue();
	o.ply_final = a.ply_final.getValue();
	o.write_problem = a.write_problem.getValue();
	o.loss_scale = a.loss_scale.getValue();
	o.solver.num_threads = a.threads.getValue();
	o.solver.max_iterations = a.max_iterations.getValue();
	o.solver.function_tolerance = a.ftol.getValue();
	o.solver.gradient_tolerance = a.gtol.getValue();
	o.solver.parameter_tolerance = a.ptol.getValue();
	o.solver.progress_to_stdout = !a.quiet.getValue();
	const std::string ls = a.linear.getValue();
	if (ls != "auto" && ls != "dense-schur" && ls != "sparse-schur")
		throw UsageError("--linear must be dense-schur, sparse-schur or auto, got '" + ls + "'");
	o.solver.linear_solver = swba::parse_linear_solver(ls);
	if (o.solver.num_threads < 1) throw UsageError("--threads must be >= 1");
	if (o.solver.max_iterations < 0) throw UsageError("--max-iterations must be >= 0");
	if (!(o.solver.function_tolerance >= 0)) throw UsageError("--function-tolerance must be >= 0");
	if (!(o.solver.gradient_tolerance >= 0)) throw UsageError("--gradient-tolerance must be >= 0");
	if (!(o.solver.parameter_tolerance >= 0)) throw UsageError("--parameter-tolerance must be >= 0");
	if (!(o.loss_scale > 0)) throw UsageError("--loss-scale must be > 0");
	swba::app::validate_usage(o.solver);
	try
	{
		o.loss = swba::parse_enum<swba::RobustLoss>(a.loss.getValue(), "loss");
	}
	catch (const std::invalid_argument& e)
	{
		throw UsageError(e.what());
	}
	return o;
}

// A failed optimisation throws (after the report): main prints "swba bal: error: optimisation failed: …", exit 1.
SWBA_REGISTER_COMMAND("bal", "bundle adjustment of a BAL problem (Snavely cameras), PLY output",
					  swba::app::app_command<BalCommandLine>(swba::apps::run_bal_app));
}  // namespace
