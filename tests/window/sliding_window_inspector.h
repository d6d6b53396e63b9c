// White-box access to the window's marginal prior for the tests (a friend of SlidingWindowEstimator):
// its information and its global SE(3) gauge directions.
#pragma once

#include <swba/core/manifold.h>
#include <swba/estimators/sliding_window.h>
#include <swba/smoother/fixed_lag_smoother.h>

#include <Eigen/Core>

namespace swba::test
{
class SlidingWindowInspector
{
   public:
	explicit SlidingWindowInspector(const estimators::SlidingWindowEstimator& est) : est_(est) {}

	/** The last marginal prior's information H = JᵀJ over its variables. */
	Eigen::MatrixXd prior_information() const
	{
		const Eigen::MatrixXd& J = est_.smoother().prior().J();
		return J.transpose() * J;
	}

	/** Stacked 6 global SE(3) gauge directions (columns) in the prior's tangent coordinates,
	 * evaluated at the prior's linearisation point (x_lin / first estimates). */
	Eigen::MatrixXd prior_gauge_directions() const
	{
		const auto& sm = est_.smoother();
		int n = 0;
		for (VariableId v : sm.prior().variables()) n += sm.problem().variable(v).manifold->tangent_size();
		Eigen::MatrixXd N = Eigen::MatrixXd::Zero(n, 6);
		int off = 0;
		for (VariableId v : sm.prior().variables())
		{
			const auto& var = sm.problem().variable(v);
			const double* x = sm.linearization_point(v);
			if (var.manifold->tangent_size() == 6)
			{
				// Global motion x ↦ x + v + w × x seen as a right perturbation of T = [R | t]:
				// δρ = Rᵀ(v + w × t), δω = Rᵀ w.
				const auto T = se3_view(x);
				const Eigen::Matrix3d Rt = T.leftCols<3>().transpose();
				N.block<3, 3>(off, 0) = Rt;
				N.block<3, 3>(off, 3) = -Rt * skew(T.col(3));
				N.block<3, 3>(off + 3, 3) = Rt;
			}
			else if (est_.is_world_point(v))
			{
				const Eigen::Vector3d p(x[0], x[1], x[2]);
				N.block<3, 3>(off, 0) = Eigen::Matrix3d::Identity();
				N.block<3, 3>(off, 3) = -skew(p);
			}
			// Inverse-depth landmarks (still anchored) are anchor-relative: invariant under a global motion.
			off += var.manifold->tangent_size();
		}
		return N;
	}

   private:
	const estimators::SlidingWindowEstimator& est_;
};
}  // namespace swba::test
