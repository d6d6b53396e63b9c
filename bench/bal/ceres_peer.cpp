// The Ceres 2.1 peer: the Snavely model as an automatically differentiated cost functor (how Ceres's
// users write it), points eliminated first (explicit ordering), SPARSE_SCHUR with SuiteSparse or
// DENSE_SCHUR.
#include <ceres/autodiff_cost_function.h>
#include <ceres/problem.h>
#include <ceres/rotation.h>
#include <ceres/solver.h>
#include <swba/core/timing.h>

#include <memory>

#include "bal_peers.h"

namespace swba::bench
{
namespace
{
/** residual = f·(1 + k1‖p‖² + k2‖p‖⁴)·p − observed, p = −P.xy/P.z, P = R(ω)·X + t. */
struct SnavelyResidual
{
	double observed_x, observed_y;

	template <typename T>
	bool operator()(const T* const camera, const T* const point, T* residual) const
	{
		T P[3];
		ceres::AngleAxisRotatePoint(camera, point, P);
		for (int i = 0; i < 3; i++) P[i] += camera[3 + i];
		const T px = -P[0] / P[2];
		const T py = -P[1] / P[2];
		const T n = px * px + py * py;
		const T scale = camera[6] * (T(1.0) + n * (camera[7] + camera[8] * n));
		residual[0] = scale * px - observed_x;
		residual[1] = scale * py - observed_y;
		return true;
	}
};
}  // namespace

PeerResult solve_ceres(const io::BalProblem& bal_in, const PeerSettings& s)
{
	io::BalProblem bal = bal_in;  // Ceres optimises the parameter arrays in place
	ceres::Problem problem;
	for (const auto& o : bal.observations)
		problem.AddResidualBlock(
			new ceres::AutoDiffCostFunction<SnavelyResidual, 2, 9, 3>(new SnavelyResidual{o.x, o.y}), nullptr,
			bal.camera(o.camera), bal.point(o.point));
	auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
	for (int j = 0; j < bal.num_points; j++) ordering->AddElementToGroup(bal.point(j), 0);
	for (int i = 0; i < bal.num_cameras; i++) ordering->AddElementToGroup(bal.camera(i), 1);

	ceres::Solver::Options o;
	o.minimizer_type = ceres::TRUST_REGION;
	o.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
	o.linear_solver_type = s.dense ? ceres::DENSE_SCHUR : ceres::SPARSE_SCHUR;
	o.sparse_linear_algebra_library_type = ceres::SUITE_SPARSE;
	o.linear_solver_ordering = ordering;
	o.num_threads = s.num_threads;
	o.max_num_iterations = s.max_iterations;
	set_tolerances(s, o);
	o.logging_type = ceres::SILENT;
	std::string why;
	if (!o.IsValid(&why)) throw std::runtime_error("Ceres options: " + why);

	ceres::Solver::Summary summary;
	const auto t0 = SteadyClock::now();
	ceres::Solve(o, &problem, &summary);
	PeerResult r = peer_result(seconds_since(t0), summary);
	r.iterations = summary.num_successful_steps + summary.num_unsuccessful_steps;
	r.termination = ceres::TerminationTypeToString(summary.termination_type) + std::string(": ") + summary.message;
	for (const auto& it : summary.iterations) r.log.push_back({it.iteration, it.cost, it.cumulative_time_in_seconds});
	return r;
}
}  // namespace swba::bench
