// The `swba bal` application: read a BAL problem, solve it with swba::solve, write PLY/BAL outputs.
#include <swba/apps/bal.h>
#include <swba/io/bal.h>
#include <swba/problems/bal.h>

#include <ostream>
#include <stdexcept>

namespace swba::apps
{
namespace
{
void write_ply_of(const std::string& path, const io::BalProblem& bal, std::ostream& log)
{
	if (path.empty()) return;
	problems::write_bal_ply(path, bal);
	log << "Wrote " << path << " (" << bal.num_cameras << " camera centres, " << bal.num_points << " points)\n";
}
}  // namespace

SolverOptions BalAppOptions::default_solver_options()
{
	SolverOptions o;
	o.num_threads = 2;
	return o;
}

void BalAppOptions::validate() const
{
	solver.validate();
	make_loss(loss, loss_scale);  // throws std::invalid_argument when the loss cannot be made
}

BalAppResult run_bal_app(const BalAppOptions& options, std::ostream& out, std::ostream& log)
{
	options.validate();
	const auto loss = make_loss(options.loss, options.loss_scale);

	io::BalProblem bal = io::read_bal(options.problem_path);
	BalAppResult result;
	result.num_behind_camera = problems::count_observations_behind_camera(bal);
	out << "BAL problem " << options.problem_path << ": " << bal.num_cameras << " cameras, " << bal.num_points
		<< " points, " << bal.observations.size() << " observations (" << result.num_behind_camera
		<< " with the point behind its camera)\n";
	write_ply_of(options.ply_initial, bal, log);

	Problem problem;
	const problems::BalVariables vars = problems::add_bal_to_problem(bal, problem, loss);
	if (vars.num_unobserved_cameras + vars.num_unobserved_points > 0)
		out << "Held constant (no observations): " << vars.num_unobserved_cameras << " cameras, "
			<< vars.num_unobserved_points << " points\n";
	out << "Loss: " << enum_name(options.loss);
	if (loss) out << " (scale " << options.loss_scale << " px)";
	out << "; threads: " << options.solver.num_threads << "\n";
	out.flush();

	result.summary = solve(problem, options.solver);
	out << result.summary.full_report();
	out.flush();
	if (!result.summary.is_solution_usable()) throw std::runtime_error("optimisation failed: " + result.summary.message);
	problems::copy_values_to_bal(problem, vars, bal);
	out << "Observations behind their camera at the solution: " << problems::count_observations_behind_camera(bal)
		<< "\n";

	out.flush();
	write_ply_of(options.ply_final, bal, log);
	if (!options.write_problem.empty())
	{
		io::write_bal(options.write_problem, bal);
		log << "Wrote " << options.write_problem << " (BAL, solution values)\n";
	}
	return result;
}
}  // namespace swba::apps
