// A BAL problem as a swba::Problem, and the Snavely camera geometry of its values (see bal.h).
#include <swba/core/manifold.h>
#include <swba/factors/snavely_reprojection.h>
#include <swba/io/ply.h>
#include <swba/problems/bal.h>

#include <algorithm>

namespace swba::problems
{
using io::BalProblem;

int count_observations_behind_camera(const BalProblem& bal)
{
	int n = 0;
	for (const auto& o : bal.observations)
	{
		const double* cam = bal.camera(o.camera);
		const Eigen::Vector3d P =
			angle_axis_rotate_point(cam, Eigen::Map<const Eigen::Vector3d>(bal.point(o.point))) +
			Eigen::Vector3d(cam[3], cam[4], cam[5]);
		if (P.z() >= 0.0) n++;
	}
	return n;
}

std::vector<Eigen::Vector3d> bal_camera_centres(const BalProblem& bal)
{
	std::vector<Eigen::Vector3d> c;
	c.reserve(static_cast<size_t>(bal.num_cameras));
	for (int i = 0; i < bal.num_cameras; i++) c.push_back(snavely_camera_centre(bal.camera(i)));
	return c;
}

void write_bal_ply(const std::string& path, const BalProblem& bal)
{
	std::vector<Eigen::Vector3d> pts;
	pts.reserve(static_cast<size_t>(bal.num_points));
	for (int j = 0; j < bal.num_points; j++) pts.emplace_back(Eigen::Map<const Eigen::Vector3d>(bal.point(j)));
	io::write_ply(path, bal_camera_centres(bal), pts);
}

namespace
{
/** Holds constant the variables of `vars` no observation reached (`seen[k]` 0); their number. */
int hold_unobserved(const std::vector<VariableId>& vars, const std::vector<char>& seen, Problem& problem)
{
	int n = 0;
	for (size_t k = 0; k < vars.size(); k++)
		if (!seen[k])
		{
			problem.set_constant(vars[k]);
			n++;
		}
	return n;
}
}  // namespace

BalVariables add_bal_to_problem(const BalProblem& bal, Problem& problem, std::shared_ptr<const LossFunction> loss)
{
	BalVariables vars;
	const auto cam_manifold = euclidean_manifold(BalProblem::kCameraParams);
	const auto point_manifold = euclidean_manifold(BalProblem::kPointParams);
	vars.cameras.reserve(static_cast<size_t>(bal.num_cameras));
	vars.points.reserve(static_cast<size_t>(bal.num_points));
	for (int i = 0; i < bal.num_cameras; i++)
		vars.cameras.push_back(problem.add_variable(bal.camera(i), cam_manifold, Group::Kept));
	for (int j = 0; j < bal.num_points; j++)
		vars.points.push_back(problem.add_variable(bal.point(j), point_manifold, Group::Eliminable));
	std::vector<char> cam_seen(static_cast<size_t>(bal.num_cameras), 0), point_seen(static_cast<size_t>(bal.num_points), 0);
	for (const auto& o : bal.observations)
	{
		problem.add_factor(std::make_shared<SnavelyReprojectionFactor>(o.x, o.y),
						   {vars.cameras[static_cast<size_t>(o.camera)], vars.points[static_cast<size_t>(o.point)]}, loss);
		cam_seen[static_cast<size_t>(o.camera)] = 1;
		point_seen[static_cast<size_t>(o.point)] = 1;
	}
	vars.num_unobserved_cameras = hold_unobserved(vars.cameras, cam_seen, problem);
	vars.num_unobserved_points = hold_unobserved(vars.points, point_seen, problem);
	return vars;
}

void copy_values_to_bal(const Problem& problem, const BalVariables& vars, BalProblem& bal)
{
	for (int i = 0; i < bal.num_cameras; i++)
	{
		const double* v = problem.value(vars.cameras[static_cast<size_t>(i)]);
		std::copy(v, v + BalProblem::kCameraParams, bal.camera(i));
	}
	for (int j = 0; j < bal.num_points; j++)
	{
		const double* v = problem.value(vars.points[static_cast<size_t>(j)]);
		std::copy(v, v + BalProblem::kPointParams, bal.point(j));
	}
}
}  // namespace swba::problems
