// The SO(3) / SE(3) / SO(2) helpers of core/lie.h against closed forms evaluated in long double,
// against MRPT (skew_symmetric3, Lie::SO<3>, Lie::SE<3>) and against identities, at ordinary
// angles, at small angles (where the series take over) and near π.
#include <swba/core/lie.h>

#include <mrpt/math/geometry.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/Lie/SE.h>
#include <mrpt/poses/Lie/SO.h>

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <vector>

using namespace swba;

namespace
{
std::mt19937& rng()
{
	static std::mt19937 gen(11);
	return gen;
}

Eigen::Vector3d random_unit()
{
	std::normal_distribution<double> n(0, 1);
	return Eigen::Vector3d(n(rng()), n(rng()), n(rng())).normalized();
}

Eigen::Matrix3d mrpt_exp(const Eigen::Vector3d& w)
{
	mrpt::math::CVectorFixedDouble<3> v;
	for (int i = 0; i < 3; i++) v[i] = w[i];
	return mrpt::poses::Lie::SO<3>::exp(v).asEigen();
}

/** Uniformly random unit vectors, drawn as tests/factors' Rng draws them (same seeds, same values). */
class UniformRng
{
   public:
	explicit UniformRng(unsigned seed) : gen_(seed) {}
	double uniform(double a, double b) { return std::uniform_real_distribution<double>(a, b)(gen_); }
	Eigen::Vector3d unit() { return Eigen::Vector3d{uniform(-1, 1), uniform(-1, 1), uniform(-1, 1)}.normalized(); }

   private:
	std::mt19937 gen_;
};

/** Rotation by `angle` about a (normalised) axis. */
Eigen::Matrix3d axis_angle(double angle, const Eigen::Vector3d& axis)
{
	return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

/** Angles exercising the series, the switch points and the neighbourhood of π. */
const std::vector<double> kAngles = {0.0, 1e-12, 1e-8, 1e-5, 0.99e-4, 1.01e-4, 1e-3, 0.0999, 0.1001, 0.3, 1.0,
									 2.0, 3.0, M_PI - 1e-3, M_PI - 1e-5};
}  // namespace

// ------------------------------------------------------------------------------------------ skew
TEST(Lie, SkewIsTheCrossProductMatrixAsMrpt)
{
	for (int k = 0; k < 20; k++)
	{
		const Eigen::Vector3d v = 3.0 * random_unit(), w = random_unit();
		const Eigen::Matrix3d S = skew(v);
		EXPECT_LE((S * w - v.cross(w)).cwiseAbs().maxCoeff(), 1e-15);
		EXPECT_EQ(S + S.transpose(), Eigen::Matrix3d::Zero());
		mrpt::math::CVectorFixedDouble<3> mv;
		for (int i = 0; i < 3; i++) mv[i] = v[i];
		EXPECT_EQ(S, mrpt::math::skew_symmetric3(mv).asEigen());
	}
}

// ------------------------------------------------------------------------ Rodrigues coefficients
TEST(Lie, RodriguesCoefficientsMatchTheClosedFormsInLongDouble)
{
	for (double theta : kAngles)
	{
		if (theta == 0.0) continue;
		// a and b in forms without cancellation; c = (θ − sin θ)/θ³ cancels even in long double below
		// θ = 0.01, where its Taylor polynomial (omitted term θ⁶/362880 < 3e-18) is the reference.
		const long double t = theta, s = std::sin(t), h = std::sin(t / 2);
		const long double a = s / t, b = 2 * h * h / (t * t);
		const long double c = theta >= 0.01 ? (t - s) / (t * t * t)
											: 1.0L / 6 - t * t / 120 + t * t * t * t / 5040;
		const RodriguesCoefficients k = rodrigues_coefficients(theta * theta);
		EXPECT_NEAR(k.a, static_cast<double>(a), 1e-15) << "theta = " << theta;
		EXPECT_NEAR(k.b, static_cast<double>(b), 1e-15) << "theta = " << theta;
		EXPECT_NEAR(k.c, static_cast<double>(c), 1e-14) << "theta = " << theta;
	}
	const RodriguesCoefficients zero = rodrigues_coefficients(0.0);
	EXPECT_EQ(zero.a, 1.0);
	EXPECT_EQ(zero.b, 0.5);
	EXPECT_EQ(zero.c, 1.0 / 6.0);
}

TEST(Lie, RodriguesSeriesAndClosedFormAgreeAtSwitch)
{
	// The series runs below θ² = 1e-2, the closed forms from there: the two neighbouring doubles.
	const RodriguesCoefficients below = rodrigues_coefficients(std::nextafter(1e-2, 0.0));
	const RodriguesCoefficients above = rodrigues_coefficients(1e-2);
	EXPECT_NEAR(below.a, above.a, 1e-15);
	EXPECT_NEAR(below.b, above.b, 1e-15);
	// c's closed form (θ − sin θ)/θ³ still cancels ~3 digits at θ = 0.1 (the series is the better side).
	EXPECT_NEAR(below.c, above.c, 1e-14);
}

TEST(Lie, RodriguesRotationIsMrptExp)
{
	for (double theta : kAngles)
	{
		const Eigen::Vector3d w = theta * random_unit();
		const RodriguesCoefficients k = rodrigues_coefficients(w.squaredNorm());
		const Eigen::Matrix3d W = skew(w);
		const Eigen::Matrix3d R = Eigen::Matrix3d::Identity() + k.a * W + k.b * W * W;
		EXPECT_LE((R - mrpt_exp(w)).cwiseAbs().maxCoeff(), 1e-15) << "theta = " << theta;
	}
}

// ------------------------------------------------------------------ SO(3) right Jacobian inverse
TEST(So3RightJacobianInverse, LinearisesLogOfProduct)
{
	// Log(Exp(φ)·Exp(δ)) ≈ φ + J_r⁻¹(φ)·δ; central differences of MRPT's Log at several angles.
	UniformRng rng(7);
	for (double theta : {0.0, 1e-9, 1e-5, 0.99e-4, 1.01e-4, 0.3, 2.0, M_PI - 1e-3, M_PI - 1e-5})
	{
		const Eigen::Vector3d phi = theta * rng.unit();
		const Eigen::Matrix3d J = so3_right_jacobian_inverse(phi);
		mrpt::math::CVectorFixedDouble<3> p;
		for (int i = 0; i < 3; i++) p[i] = phi[i];
		const Eigen::Matrix3d R = mrpt::poses::Lie::SO<3>::exp(p).asEigen();
		const double h = 1e-6;
		Eigen::Matrix3d N;
		for (int c = 0; c < 3; c++)
		{
			Eigen::Vector3d d = Eigen::Vector3d::Zero();
			d[c] = h;
			const Eigen::Matrix3d Xp = R * axis_angle(h, d);
			const Eigen::Matrix3d Xm = R * axis_angle(-h, d);
			N.col(c) = (se3_pseudo_log(Xp, Eigen::Vector3d::Zero()).tail<3>() -
						se3_pseudo_log(Xm, Eigen::Vector3d::Zero()).tail<3>()) /
					   (2 * h);
		}
		EXPECT_LE((J - N).cwiseAbs().maxCoeff(), 1e-6) << "theta = " << theta;
	}
}

TEST(Lie, RightJacobianInverseIdentities)
{
	EXPECT_EQ(so3_right_jacobian_inverse(Eigen::Vector3d::Zero()), Eigen::Matrix3d::Identity());
	for (double theta : kAngles)
	{
		// J_r⁻¹(φ)·φ = φ, and J_r⁻¹(−φ) = J_r⁻¹(φ)ᵀ (J_l = J_rᵀ).
		const Eigen::Vector3d phi = theta * random_unit();
		const Eigen::Matrix3d J = so3_right_jacobian_inverse(phi);
		EXPECT_LE((J * phi - phi).cwiseAbs().maxCoeff(), 1e-15) << "theta = " << theta;
		EXPECT_LE((so3_right_jacobian_inverse(-phi) - J.transpose()).cwiseAbs().maxCoeff(), 1e-15);
		// Inverse of the right Jacobian J_r = I − b·W + c·W² (Rodrigues coefficients).
		const RodriguesCoefficients k = rodrigues_coefficients(theta * theta);
		const Eigen::Matrix3d W = skew(phi);
		const Eigen::Matrix3d Jr = Eigen::Matrix3d::Identity() - k.b * W + k.c * W * W;
		EXPECT_LE((J * Jr - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-11) << "theta = " << theta;
	}
}

TEST(So3RightJacobianInverse, SeriesAndClosedFormAgreeAtSwitch)
{
	const Eigen::Vector3d axis = Eigen::Vector3d(1, -2, 0.5).normalized();
	const Eigen::Matrix3d below = so3_right_jacobian_inverse((1e-4 * (1 - 1e-12)) * axis);
	const Eigen::Matrix3d above = so3_right_jacobian_inverse((1e-4 * (1 + 1e-12)) * axis);
	EXPECT_LE((below - above).cwiseAbs().maxCoeff(), 1e-15);
}

// -------------------------------------------------------------------------------- SE(3) pseudo-log
TEST(Lie, Se3PseudoLogIsMrptSe3Log)
{
	for (double theta : kAngles)
	{
		const Eigen::Vector3d w = theta * random_unit();
		const Eigen::Vector3d t = 10.0 * random_unit();
		const Eigen::Matrix3d R = mrpt_exp(w);
		mrpt::math::CMatrixDouble33 M;
		M.asEigen() = R;
		const mrpt::poses::CPose3D P(M, mrpt::math::CVectorFixedDouble<3>({t[0], t[1], t[2]}));
		const auto v = mrpt::poses::Lie::SE<3>::log(P);
		const Eigen::Matrix<double, 6, 1> r = se3_pseudo_log(R, t);
		for (int i = 0; i < 6; i++) EXPECT_EQ(r[i], v[i]) << "theta = " << theta << ", i = " << i;
		// Pseudo-log: the translation is t itself (not V(ω)⁻¹·t).
		EXPECT_EQ(r.head<3>(), t);
	}
}

TEST(Lie, Se3PseudoLogInvertsExp)
{
	for (double theta : kAngles)
	{
		const Eigen::Vector3d w = theta * random_unit();
		const Eigen::Matrix<double, 6, 1> r = se3_pseudo_log(mrpt_exp(w), Eigen::Vector3d(1, 2, 3));
		EXPECT_LE((r.tail<3>() - w).cwiseAbs().maxCoeff(), 1e-12) << "theta = " << theta;
	}
	// Within ~1e-7 of π MRPT's Log returns angle π about the right axis: the error is the distance to
	// π; at π itself ω and −ω are the same rotation, so only Exp(Log(R)) = R is checked.
	for (double theta : {M_PI - 1e-7, M_PI - 1e-9, M_PI})
	{
		const Eigen::Vector3d w = theta * random_unit();
		const Eigen::Matrix3d R = mrpt_exp(w);
		const Eigen::Vector3d r = se3_pseudo_log(R, Eigen::Vector3d::Zero()).tail<3>();
		EXPECT_NEAR(r.norm(), theta, 1.5e-7) << "theta = " << theta;
		EXPECT_LE((mrpt_exp(r) - R).cwiseAbs().maxCoeff(), 2e-7) << "theta = " << theta;
	}
}

// ------------------------------------------------------------------------------- SO(3) projection
TEST(Lie, ProjectionKeepsRotationsAndIsNearest)
{
	for (double theta : kAngles)
	{
		const Eigen::Matrix3d R = mrpt_exp(theta * random_unit());
		EXPECT_LE((project_to_so3(R) - R).cwiseAbs().maxCoeff(), 1e-14) << "theta = " << theta;
		// Perturbed: the result is a rotation, and no farther from A than R is.
		std::normal_distribution<double> n(0, 1e-3);
		Eigen::Matrix3d A = R;
		for (int i = 0; i < 9; i++) A.data()[i] += n(rng());
		const Eigen::Matrix3d P = project_to_so3(A);
		EXPECT_LE((P.transpose() * P - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-14);
		EXPECT_NEAR(P.determinant(), 1.0, 1e-14);
		EXPECT_LE((P - A).norm(), (R - A).norm() + 1e-15) << "theta = " << theta;
		// Scale does not matter: the polar factor of s·A is that of A.
		EXPECT_LE((project_to_so3(7.0 * A) - P).cwiseAbs().maxCoeff(), 1e-14);
	}
}

TEST(Lie, ProjectionOfAReflectionIsARotation)
{
	const Eigen::Matrix3d R = mrpt_exp(Eigen::Vector3d(0.3, -0.2, 0.5));
	const Eigen::Matrix3d A = R * Eigen::Vector3d(1, 1, -1).asDiagonal();  // det −1
	const Eigen::Matrix3d P = project_to_so3(A);
	EXPECT_NEAR(P.determinant(), 1.0, 1e-14);
	EXPECT_LE((P.transpose() * P - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-14);
}

// ------------------------------------------------------------------------------------ angle wrap
TEST(WrapToPi, RangeIsMinusPiExclusiveToPiInclusive)
{
	EXPECT_EQ(wrap_to_pi(M_PI), M_PI);
	EXPECT_EQ(wrap_to_pi(-M_PI), M_PI);
	EXPECT_NEAR(wrap_to_pi(3 * M_PI), M_PI, 1e-15);
	EXPECT_EQ(wrap_to_pi(0.0), 0.0);
	EXPECT_NEAR(wrap_to_pi(-1.5 * M_PI), 0.5 * M_PI, 1e-15);
	EXPECT_NEAR(wrap_to_pi(2 * M_PI + 0.1), 0.1, 1e-15);
	EXPECT_NEAR(wrap_to_pi(-2 * M_PI - 0.1), -0.1, 1e-15);
	EXPECT_NEAR(wrap_to_pi(M_PI + 1e-3), -M_PI + 1e-3, 1e-15);
	EXPECT_NEAR(wrap_to_pi(-M_PI - 1e-3), M_PI - 1e-3, 1e-15);
	for (double a = -20.0; a <= 20.0; a += 0.01)
	{
		const double w = wrap_to_pi(a);
		ASSERT_GT(w, -M_PI);
		ASSERT_LE(w, M_PI);
		ASSERT_NEAR(std::remainder(a - w, 2 * M_PI), 0.0, 1e-12);
	}
}

TEST(WrapToPi, InRangeAnglesComeBackBitForBit)
{
	// Small residuals keep their low bits (no rounding through ±π).
	for (double a : {1e-300, 1e-17, -1e-17, 0.1, -0.1, 1.0, -3.0, M_PI - 1e-15, -M_PI + 1e-15})
		EXPECT_EQ(wrap_to_pi(a), a);
	EXPECT_EQ(wrap_to_pi(2 * M_PI + 1e-3) + 2 * M_PI, 2 * M_PI + 1e-3);
}
