/** \file pose_error.h
 * The SE(3) error shared by the factors that compare a pose built from their variables with a
 * measured pose Z (BetweenPoseFactor: X = Ti⁻¹·Tj; PosePriorFactor: X = T).
 *
 *   r = PseudoLog(E) = [t_E, Log(R_E)] ∈ R⁶,  E = Z⁻¹·X,
 *
 * and, for the right perturbation X ⊞ δ = X·PseudoExp(δ) (SE3Manifold), ∂r/∂δ = [[R_E, 0], [0, J_r⁻¹(φ)]]
 * with φ = Log(R_E) (see swba/core/lie.h). */
#pragma once

#include <swba/core/factor.h>
#include <swba/core/lie.h>

#include <mrpt/poses/CPose3D.h>

#include <Eigen/Core>
#include <vector>

namespace swba
{
/** Base of the factors whose residual is PseudoLog(Z⁻¹·X) for a measured pose Z. */
class PoseErrorFactor : public Factor
{
   public:
	/** Z. */
	const mrpt::poses::CPose3D& measured() const { return measured_; }

   protected:
	PoseErrorFactor(const mrpt::poses::CPose3D& measured, std::vector<int> tangent_dims);

	/** Writes r = PseudoLog(E) of E = [R_E | t_E] to `residual` and, if `Jinv` is given, J_r⁻¹(Log R_E)
	 * to it. Returns false (nothing written) when r is not finite. */
	static bool write_error(const Eigen::Matrix3d& RE, const Eigen::Vector3d& tE, double* residual,
							Eigen::Matrix3d* Jinv);
	/** Writes ∂r/∂δX = [[R_E, 0], [0, J_r⁻¹]] (6×6, row-major) to `J`. */
	static void write_error_jacobian(const Eigen::Matrix3d& RE, const Eigen::Matrix3d& Jinv, double* J);

	/** R_Z and t_Z. */
	const Eigen::Matrix3d& measured_rotation() const { return Rz_; }
	const Eigen::Vector3d& measured_translation() const { return tz_; }

   private:
	mrpt::poses::CPose3D measured_;
	Eigen::Matrix3d Rz_;
	Eigen::Vector3d tz_;
};
}  // namespace swba
