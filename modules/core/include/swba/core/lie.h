/** \file lie.h
 * SO(3) / SE(3) / SO(2) helpers shared by the manifolds, the factors and the initialisers, in the
 * conventions of mrpt::poses::Lie (right perturbations, δ = [ρ, ω] translation first). Where MRPT 2.5
 * has the operation (SO(3) Log) these are thin wrappers over mrpt::poses::Lie; note that MRPT's
 * Lie::SE<3>::exp/log are *pseudo* exp/log (the translation is not multiplied by V(ω)), which is
 * what se3_pseudo_log computes. The closed forms that cancel near θ = 0 are evaluated by their
 * Taylor series there; those series live in one place (lie.cpp). */
#pragma once

#include <Eigen/Core>

namespace swba
{
/** Skew-symmetric matrix [v]× such that [v]× w = v × w. */
inline Eigen::Matrix3d skew(const Eigen::Vector3d& v)
{
	Eigen::Matrix3d S;
	S << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
	return S;
}

/** Coefficients of Rodrigues' formula R(ω) = I + a·W + b·W² and of the left Jacobian
 * J_l(ω) = I + b·W + c·W² of SO(3) (W = [ω]×, θ = ‖ω‖):
 * a = sin θ/θ, b = (1 − cos θ)/θ², c = (θ − sin θ)/θ³. */
struct RodriguesCoefficients
{
	double a, b, c;
};

/** a, b, c for θ² = ‖ω‖². Below θ = 0.1 the closed forms lose digits to cancellation (c: ~6e-8
 * relative at θ = 1e-4), so their Taylor series are used there; the first omitted term is < 3e-17
 * relative at θ = 0.1. */
RodriguesCoefficients rodrigues_coefficients(double theta_sq);

/** Right Jacobian of SO(3): Exp(φ + δ) = Exp(φ)·Exp(J_r(φ)·δ) + O(δ²); J_r(φ) = I − b·W + c·W² with
 * W = [φ]× and b, c of rodrigues_coefficients. */
Eigen::Matrix3d so3_right_jacobian(const Eigen::Vector3d& phi);

/** Exp(φ) of SO(3) (mrpt::poses::Lie::SO<3>::exp). */
Eigen::Matrix3d so3_exp(const Eigen::Vector3d& phi);

/** Log(R) of SO(3) through a unit quaternion (Eigen::AngleAxisd), accurate up to and at π. */
Eigen::Vector3d so3_log(const Eigen::Matrix3d& R);

/** Inverse right Jacobian of SO(3): Log(Exp(φ)·Exp(δ)) = φ + J_r⁻¹(φ)·δ + O(δ²), for ‖φ‖ < 2π.
 * J_r⁻¹(φ) = I + ½[φ]× + (1/θ² − (1 + cos θ)/(2θ sin θ))·[φ]×², θ = ‖φ‖ (series below θ = 1e-4). */
Eigen::Matrix3d so3_right_jacobian_inverse(const Eigen::Vector3d& phi);

/** PseudoLog(E) = [t_E, Log(R_E)] of an SE(3) transform E = [R_E | t_E], as mrpt::poses::Lie::SE<3>::log
 * (rotation part by Lie::SO<3>::log, which rounds angles within ~1e-7 of π to π). */
Eigen::Matrix<double, 6, 1> se3_pseudo_log(const Eigen::Matrix3d& R, const Eigen::Vector3d& t);

/** The rotation nearest to A in the Frobenius norm: U·Vᵀ from the SVD A = U·Σ·Vᵀ, with the sign of
 * U's last column flipped when det(U·Vᵀ) < 0 (so the result is a rotation, never a reflection). */
Eigen::Matrix3d project_to_so3(const Eigen::Matrix3d& A);

/** An angle wrapped into (−π, π] by std::remainder, exactly: the result differs from a by an
 * integer multiple of 2π (as doubles), so small angles keep all their low bits (unlike
 * mrpt::math::wrapToPi, which computes wrapTo2Pi(a + π) − π). */
double wrap_to_pi(double a);
}  // namespace swba
