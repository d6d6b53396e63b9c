// The `swba pgo` application: read a g2o pose graph, initialise, optimise, write it back (see pgo.h).
#include <swba/apps/pgo.h>

#include <ostream>
#include <stdexcept>

namespace swba::apps
{
void PgoAppOptions::validate() const
{
	if (!(prior_sigma > 0)) throw std::invalid_argument("prior_sigma must be > 0");
	make_loss(loss, loss_scale);  // throws std::invalid_argument when the loss cannot be made
	if (solver.linear_solver == LinearSolverType::DenseSchur || solver.linear_solver == LinearSolverType::SparseSchur)
		throw std::invalid_argument("a pose graph has no variables to eliminate (use auto, dense-normal or sparse-normal)");
	solver.validate();
}

problems::PoseGraphInitOptions PgoAppOptions::init_options() const
{
	problems::PoseGraphInitOptions o;
	o.method = init;
	o.solve_positions = init_solve_positions;
	o.rotation_error = rotation_error;
	return o;
}

problems::PoseGraphProblemOptions PgoAppOptions::problem_options() const
{
	problems::PoseGraphProblemOptions o;
	o.gauge = gauge;
	o.prior_sigma = prior_sigma;
	o.loss = make_loss(loss, loss_scale);
	o.rotation_error = rotation_error;
	return o;
}

problems::PoseGraphInitSummary initialize_pgo(io::PoseGraph& graph, const PgoAppOptions& options)
{
	return problems::initialize_pose_graph(graph, options.init_options());
}

problems::PoseGraphProblem build_pgo_problem(const io::PoseGraph& graph, const PgoAppOptions& options)
{
	return problems::build_pose_graph_problem(graph, options.problem_options());
}

Summary solve_pgo(problems::PoseGraphProblem& problem, io::PoseGraph& graph, const PgoAppOptions& options)
{
	const Summary summary = solve(problem.problem, options.solver);
	problems::update_pose_graph(graph, problem);
	return summary;
}

PgoAppResult run_pgo_app(const PgoAppOptions& options, std::ostream& out, std::ostream& log)
{
	options.validate();
	const io::G2oReadOptions& read = options.read;
	io::PoseGraph graph = io::read_g2o(options.input_path, read);
	if (const auto skipped = graph.skipped_summary(); !skipped.empty()) log << "swba pgo: warning: " << skipped << "\n";
	if (graph.num_vertices() == 0)
		throw std::runtime_error("g2o file '" + options.input_path +
								 "': no vertices (no VERTEX_SE3:QUAT or VERTEX_SE2 line): nothing to optimise");
	PgoAppResult result;
	const bool repair = read.information == io::InformationPolicy::Repair;
	result.repaired_information = graph.repaired_information.count;
	// Repairing changes the problem: always said (count 0 included), never silent.
	if (repair)
		log << "swba pgo: " << graph.repaired_information.summary(graph.num_edges(), read.relative_floor) << "\n";
	out << "Pose graph " << options.input_path << ": " << graph.num_vertices() << " vertices, " << graph.num_edges()
		<< " edges (" << (graph.is_2d() ? "2D SE2" : "3D SE3:QUAT") << "), " << graph.fixed.size() << " FIX";
	if (repair) out << ", " << result.repaired_information << " information matrices repaired";
	out << "\n";
	result.init = initialize_pgo(graph, options);
	out << "Initialisation " << result.init.brief() << "\n";
	auto pp = build_pgo_problem(graph, options);
	result.num_constant = pp.num_constant;
	result.has_prior = pp.has_prior;
	out << "Gauge: " << problems::to_string(options.gauge) << " (" << pp.num_constant << " constant vertices"
		<< (pp.has_prior ? ", prior on the first vertex" : "") << ")\n";

	result.summary = solve_pgo(pp, graph, options);
	out << result.summary.full_report();
	if (options.loss != RobustLoss::None || pp.has_prior)
		out << "Edge cost without loss/prior: " << problems::pose_graph_cost(graph, options.rotation_error) << "\n";
	if (!result.summary.is_solution_usable()) throw std::runtime_error("optimisation failed: " + result.summary.message);
	// A variable whose every factor left its domain keeps the value the step gave it: never a success.
	if (const std::string bad = graph.first_non_finite_vertex(); !bad.empty())
		throw std::runtime_error("optimisation failed: " + bad + " is not finite at the solution");
	if (!options.output_path.empty())
	{
		io::write_g2o(graph, options.output_path);
		out.flush();
		log << "Wrote " << options.output_path << "\n";
	}
	return result;
}
}  // namespace swba::apps
