/** \file relative_pose.h
 * Pose-graph factors in the formulation of the g2o / Ceres `pose_graph_3d` reference model, so that
 * costs are directly comparable with a Ceres solve of the same graph.
 *
 * 3D (variables on SE3Manifold, right perturbations δ = [ρ, ω], T ⊞ δ = T·PseudoExp(δ)):
 *   r = [ R_aᵀ(t_b − t_a) − t_ab ;  2·vec(q(E)) ]
 * with the rotation error E chosen by RotationError:
 *   G2o:          E = R_abᵀ·R_aᵀ·R_b   (2·vec(q_ab⁻¹·q_a⁻¹·q_b): g2o's EdgeSE3 rotation error, Z⁻¹·Ti⁻¹·Tj)
 *   CeresExample: E = R_ab·R_bᵀ·R_a    (2·vec(q_ab·(q_a⁻¹·q_b)⁻¹): Ceres's pose_graph_3d example)
 * The two differ by a rotation of the error vector by R_ab (vec q(F) = −R_ab·vec q(E)), which matters
 * when the rotation information is not isotropic (sphere2500). q(E) is the unit quaternion of E with
 * w ≥ 0 (the error is measured the short way round). For small errors 2·vec(q(E)) equals the
 * rotation vector of E (2·sin(θ/2)·u ≈ θ·u), so the g2o information block of (qx, qy, qz) applies
 * to it without rescaling: the residual is ordered (x, y, z, qx, qy, qz) exactly like the 21
 * upper-triangular information entries of EDGE_SE3:QUAT.
 *
 * 2D (native SE(2), variables on EuclideanManifold(3) holding (x, y, θ)):
 *   r = [ R(θ_a)ᵀ(p_b − p_a) − p_ab ;  wrap(θ_b − θ_a − θ_ab) ],  wrap to (−π, π],
 * ordered (x, y, θ) like EDGE_SE2's 6 information entries. */
#pragma once

#include <swba/core/factor.h>
#include <swba/core/names.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>

namespace swba
{
/** Which quaternion error the rotation part of the 3D residual uses (see the file comment). */
enum class RotationError
{
	G2o,          ///< 2·vec(q_ab⁻¹·q_a⁻¹·q_b) (default)
	CeresExample  ///< 2·vec(q_ab·(q_a⁻¹·q_b)⁻¹)
};
constexpr std::array<EnumName<RotationError>, 2> enum_names(RotationError)
{
	return {{{RotationError::G2o, "g2o"}, {RotationError::CeresExample, "ceres"}}};
}

/** Relative SE(3) pose measurement Z = (q_ab, t_ab) of pose b in the frame of pose a. */
class RelativePoseFactor final : public Factor
{
   public:
	/** `q_ab` is normalised here. */
	RelativePoseFactor(const Eigen::Quaterniond& q_ab, const Eigen::Vector3d& t_ab,
					   RotationError rotation_error = RotationError::G2o);

	bool evaluate(const double* const* x, double* residual, double* const* jacobians) const override;

	const Eigen::Quaterniond& rotation() const { return q_ab_; }
	const Eigen::Vector3d& translation() const { return t_ab_; }

   private:
	Eigen::Quaterniond q_ab_;
	Eigen::Matrix3d R_ab_;
	Eigen::Vector3d t_ab_;
	RotationError rotation_error_;
};

/** Unary prior on an SE(3) pose with the same residual as RelativePoseFactor with pose a fixed to
 * the prior mean T0: r = [R0ᵀ(t − t0) ; 2·vec(q(R0ᵀR))]. Used for the prior gauge. */
class PosePriorQuatFactor final : public Factor
{
   public:
	PosePriorQuatFactor(const Eigen::Quaterniond& q0, const Eigen::Vector3d& t0);
	bool evaluate(const double* const* x, double* residual, double* const* jacobians) const override;

   private:
	Eigen::Matrix3d R0_T_;
	Eigen::Vector3d t0_;
};

/** Base of the SE(2) factors: the error of pose b in the frame of pose a against a measurement
 * z = (x_z, y_z, θ_z), r = [R(θ_a)ᵀ(p_b − p_a) − p_z ; wrap(θ_b − θ_a − θ_z)], over variables (x, y, θ) on
 * EuclideanManifold(3). Either both poses are variables (x[0] = a, x[1] = b) or a is held fixed and
 * the factor is unary (x[0] = b). */
class Pose2dErrorFactor : public Factor
{
   public:
	bool evaluate(const double* const* x, double* residual, double* const* jacobians) const final;

   protected:
	/** Binary: a and b are the variables. */
	explicit Pose2dErrorFactor(const Eigen::Vector3d& z);
	/** Unary: a is fixed at `fixed_a`, b is the variable. */
	Pose2dErrorFactor(const Eigen::Vector3d& z, const Eigen::Vector3d& fixed_a);

   private:
	Eigen::Vector3d z_, fixed_a_;
};

/** Relative SE(2) measurement (x_ab, y_ab, θ_ab) of pose b in the frame of pose a. */
class RelativePose2dFactor final : public Pose2dErrorFactor
{
   public:
	RelativePose2dFactor(double x_ab, double y_ab, double theta_ab);
};

/** Unary SE(2) prior: r = [R(θ0)ᵀ(p − p0) ; wrap(θ − θ0)], the zero measurement from the fixed pose
 * (x0, y0, θ0). */
class PosePrior2dFactor final : public Pose2dErrorFactor
{
   public:
	PosePrior2dFactor(double x0, double y0, double theta0);
};
}  // namespace swba
