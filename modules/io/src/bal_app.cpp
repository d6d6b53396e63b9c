// The `swba bal` application: read a BAL problem, solve it with swba::solve, write PLY/BAL outputs.
#include <swba/io/bal.h>

#include <ostream>

namespace swba::io
{
BalAppResult run_bal_app(const BalAppOptions& options, std::ostream& out)
{
	std::string why;
	if (!options.solver.is_valid(&why)) throw std::invalid_argument(why);
	const auto loss = make_loss(options.loss, options.loss_scale);  // validates name and scale first

	BalProblem bal = read_bal(options.problem_path);
	BalAppResult result;
	result.num_behind_camera = count_observations_behind_camera(bal);
	out << "BAL problem " << options.problem_path << ": " << bal.num_cameras << " cameras, " << bal.num_points
		<< " points, " << bal.observations.size() << " observations (" << result.num_behind_camera
		<< " with the point behind its camera)\n";
	if (!options.ply_initial.empty())
	{
		write_bal_ply(options.ply_initial, bal);
		out << "Wrote " << options.ply_initial << " (" << bal.num_cameras << " camera centres, " << bal.num_points
			<< " points)\n";
	}

	Problem problem;
	const BalVariables vars = add_bal_to_problem(bal, problem, loss);
	if (vars.num_unobserved_cameras + vars.num_unobserved_points > 0)
		out << "Held constant (no observations): " << vars.num_unobserved_cameras << " cameras, "
			<< vars.num_unobserved_points << " points\n";
	out << "Loss: " << options.loss;
	if (loss) out << " (scale " << options.loss_scale << " px)";
	out << "; threads: " << options.solver.num_threads << "\n";
	out.flush();

	result.summary = solve(problem, options.solver);
	out << result.summary.full_report();
	copy_values_to_bal(problem, vars, bal);
	out << "Observations behind their camera at the solution: " << count_observations_behind_camera(bal) << "\n";

	if (!options.ply_final.empty())
	{
		write_bal_ply(options.ply_final, bal);
		out << "Wrote " << options.ply_final << " (" << bal.num_cameras << " camera centres, " << bal.num_points
			<< " points)\n";
	}
	if (!options.write_problem.empty())
	{
		write_bal(options.write_problem, bal);
		out << "Wrote " << options.write_problem << " (BAL, solution values)\n";
	}
	return result;
}
}  // namespace swba::io
