// Changing a landmark's parameterisation when its anchor leaves the window: re-anchoring (inverse depth
// in a newer pose's sensor frame) or the switch to world XYZ, with the matching first-order change of
// variables in the marginal prior (smoother::FixedLagSmoother::change_prior_variable).
#include "range_bearing_graph.h"

#include <stdexcept>
#include <string>

namespace swba::estimators::detail
{
namespace
{
using smoother::VariableChange;
/** The range-bearing model's Jacobians as Factor::evaluate writes them (row-major). */
using PoseJacobian = Eigen::Matrix<double, 3, 6, Eigen::RowMajor>;
using PointJacobian = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;

std::vector<double> to_vector(const Eigen::Vector3d& x) { return std::vector<double>(x.data(), x.data() + 3); }

/** Evaluates the range-bearing model `h` of the measurement z = [1, 0, 0] (so that r = h − [1, 0, 0])
 * at `xs` with Jacobians into `js`, and sets D = ∂λ/∂h for λ = [yaw, pitch, 1/range]: the chain from
 * h to an inverse-depth landmark. False when the model is undefined there. */
bool inverse_depth_jacobian(const Factor& h, const double* const* xs, double* const* js, Eigen::Matrix3d& D)
{
	Eigen::Vector3d r;
	if (!h.evaluate(xs, r.data(), js)) return false;
	const double range = r[0] + 1.0;
	D << 0, 1, 0, 0, 0, 1, -1.0 / (range * range), 0, 0;
	return true;
}
}  // namespace

void RangeBearingGraph::convert_to_world_xyz(std::int32_t id)
{
	Landmark& lm = store_.at(id);
	Problem& problem = smoother_.problem();
	const std::size_t a = lm.anchor_step;
	const VariableId va = poses_[a].var, vl = lm.var;
	const Eigen::Vector3d lam = Eigen::Map<const Eigen::Vector3d>(problem.value(vl));
	const Eigen::Vector3d p = inverse_depth_to_world(problem.value(va), poses_[a].sensor, lam);
	const VariableId vp = problem.add_variable(p, euclidean_manifold(3), Group::Eliminable);

	const auto change = [&](const smoother::PriorPoints& lin) {
		const Eigen::Vector3d lam_lin = Eigen::Map<const Eigen::Vector3d>(lin.old_lin.data());
		const Eigen::Vector3d p_lin = inverse_depth_to_world(lin.others_lin[0].data(), poses_[a].sensor, lam_lin);
		// Jacobians at the first estimates (or the current values without FEJ).
		const double* Ta_f = smoother_.linearization_point(va);
		const Eigen::Vector3d lam_f = Eigen::Map<const Eigen::Vector3d>(smoother_.linearization_point(vl));
		const Eigen::Vector3d p_f = inverse_depth_to_world(Ta_f, poses_[a].sensor, lam_f);
		const RangeBearingXyzFactor h_of({1.0, 0.0, 0.0}, poses_[a].sensor);
		PoseJacobian Ha;
		PointJacobian Hp;
		Eigen::Matrix3d D;
		const double* xs[2] = {Ta_f, p_f.data()};
		double* js[2] = {Ha.data(), Hp.data()};
		if (!inverse_depth_jacobian(h_of, xs, js, D))
			throw std::runtime_error("landmark " + std::to_string(lm.id) + ": range-bearing model undefined at its anchor");
		return VariableChange{vl, vp, to_vector(p_lin), to_vector(p_f), D, Hp, {{va, Ha}}};
	};
	if (!smoother_.change_prior_variable(vl, {va}, change))
		throw std::logic_error("convert_to_world_xyz: landmark " + std::to_string(lm.id) + " is not in the prior");

	lm.world_xyz = true;
	replace_landmark_variable(lm, vp);
}

void RangeBearingGraph::reanchor(std::int32_t id, std::size_t b)
{
	Landmark& lm = store_.at(id);
	Problem& problem = smoother_.problem();
	const std::size_t a = lm.anchor_step;
	const Eigen::Vector3d lam = Eigen::Map<const Eigen::Vector3d>(problem.value(lm.var));
	Eigen::Vector3d lam_new;
	try
	{
		lam_new = reanchor_inverse_depth(problem.value(poses_[a].var), poses_[a].sensor, problem.value(poses_[b].var),
										 poses_[b].sensor, lam);
	}
	catch (const std::invalid_argument& e)
	{
		throw std::runtime_error("re-anchoring landmark " + std::to_string(lm.id) + " at time " +
								 std::to_string(poses_[b].time) + ": " + e.what() + " (the estimate diverged)");
	}
	const VariableId vl2 = problem.add_variable(lam_new, euclidean_manifold(3), Group::Eliminable);
	lm.anchor_step = b;
	replace_landmark_variable(lm, vl2);
}
}  // namespace swba::estimators::detail
