// Factor whitening: set_information rejects what is not symmetric positive definite, and W = Lᵀ
// (Λ = L·Lᵀ) makes ‖W r‖² = rᵀΛr and W J the whitened Jacobian (WᵀW = Λ).
#include <swba/core/factor.h>

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <limits>
#include <random>

namespace
{
using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/** r = A·x − z over one Euclidean variable (3 residuals, 2 unknowns). Test-only. */
class LinearTestFactor final : public swba::Factor
{
   public:
	LinearTestFactor(const RowMatrix& A, const Eigen::Vector3d& z) : Factor(3, {2}), A_(A), z_(z) {}
	bool evaluate(const double* const* x, double* residual, double* const* jacobians) const override
	{
		const Eigen::Vector2d xv(x[0][0], x[0][1]);
		Eigen::Map<Eigen::Vector3d> r(residual);
		r = A_ * xv - z_;
		if (jacobians && jacobians[0]) Eigen::Map<RowMatrix>(jacobians[0], 3, 2) = A_;
		return true;
	}

   private:
	RowMatrix A_;
	Eigen::Vector3d z_;
};

LinearTestFactor make_factor()
{
	RowMatrix A(3, 2);
	A << 1.0, 2.0, -0.5, 0.3, 4.0, -1.0;
	return LinearTestFactor(A, Eigen::Vector3d(0.2, -0.7, 1.1));
}

/** The factor's residual and Jacobian at x, raw and whitened. */
struct Evaluation
{
	Eigen::Vector3d r, rw;
	RowMatrix J = RowMatrix(3, 2), Jw = RowMatrix(3, 2);
};

Evaluation evaluate_both(const swba::Factor& f, const double (&xv)[2])
{
	const double* x[1] = {xv};
	Evaluation e;
	double* jp[1] = {e.J.data()};
	double* jwp[1] = {e.Jw.data()};
	EXPECT_TRUE(f.evaluate(x, e.r.data(), jp));
	EXPECT_TRUE(f.evaluate_whitened(x, e.rw.data(), jwp));
	return e;
}

Eigen::Matrix3d spd_information()
{
	Eigen::Matrix3d B;
	B << 2.0, 0.3, -0.1, 0.4, 1.5, 0.2, -0.6, 0.1, 3.0;
	return B * B.transpose() + 0.1 * Eigen::Matrix3d::Identity();  // full, not diagonal
}
}  // namespace

TEST(FactorInformation, RejectsNonSymmetricNonPositiveDefiniteAndBadSizes)
{
	auto f = make_factor();
	Eigen::Matrix3d L = spd_information();
	Eigen::Matrix3d asym = L;
	asym(0, 1) += 0.5;
	EXPECT_THROW(f.set_information(asym), std::invalid_argument);
	Eigen::Matrix3d indefinite = Eigen::Vector3d(1.0, -2.0, 3.0).asDiagonal();
	EXPECT_THROW(f.set_information(indefinite), std::invalid_argument);
	EXPECT_THROW(f.set_information(Eigen::Matrix3d::Zero()), std::invalid_argument);
	Eigen::Matrix3d singular = Eigen::Vector3d(1.0, 0.0, 1.0).asDiagonal();
	EXPECT_THROW(f.set_information(singular), std::invalid_argument);
	EXPECT_THROW(f.set_information(-Eigen::Matrix3d::Identity()), std::invalid_argument);
	EXPECT_THROW(f.set_information(Eigen::Matrix2d::Identity()), std::invalid_argument);
	Eigen::Matrix3d nan = L;
	nan(2, 2) = std::numeric_limits<double>::quiet_NaN();
	EXPECT_THROW(f.set_information(nan), std::invalid_argument);
	EXPECT_THROW(f.set_sqrt_information(Eigen::Matrix2d::Identity()), std::invalid_argument);
	EXPECT_THROW(f.set_sigma(0.0), std::invalid_argument);
	EXPECT_THROW(f.set_sigma(-1.0), std::invalid_argument);
	// None of the rejected calls left a whitening behind.
	EXPECT_FALSE(f.has_sqrt_information());
}

TEST(FactorInformation, WhiteningGivesMahalanobisNorm)
{
	auto f = make_factor();
	const Eigen::Matrix3d Lambda = spd_information();
	f.set_information(Lambda);
	ASSERT_TRUE(f.has_sqrt_information());
	const Eigen::MatrixXd W = f.sqrt_information();
	// W = Lᵀ: upper triangular with WᵀW = Λ.
	EXPECT_LE((W.transpose() * W - Lambda).cwiseAbs().maxCoeff(), 1e-12 * Lambda.norm());
	EXPECT_EQ(W(1, 0), 0.0);
	EXPECT_EQ(W(2, 0), 0.0);
	EXPECT_EQ(W(2, 1), 0.0);

	std::mt19937 rng(11);
	std::normal_distribution<double> g(0.0, 2.0);
	for (int trial = 0; trial < 10; trial++)
	{
		const double xv[2] = {g(rng), g(rng)};
		const auto [r, rw, J, Jw] = evaluate_both(f, xv);
		const double mahalanobis = r.dot(Lambda * r);
		EXPECT_NEAR(rw.squaredNorm(), mahalanobis, 1e-12 * mahalanobis);
		// Whitened normal equations equal the weighted ones: JwᵀJw = JᵀΛJ, Jwᵀrw = JᵀΛr.
		const Eigen::Matrix2d H = Jw.transpose() * Jw, H_expected = J.transpose() * Lambda * J;
		EXPECT_LE((H - H_expected).cwiseAbs().maxCoeff(), 1e-12 * H_expected.norm());
		const Eigen::Vector2d b = Jw.transpose() * rw, b_expected = J.transpose() * Lambda * r;
		EXPECT_LE((b - b_expected).cwiseAbs().maxCoeff(), 1e-12 * std::max(1.0, b_expected.norm()));
		// Applying L instead of Lᵀ (Ceres's pose_graph_3d pitfall) would not give rᵀΛr for this full Λ.
		const Eigen::Vector3d wrong = W.transpose() * r;
		EXPECT_GT(std::abs(wrong.squaredNorm() - mahalanobis), 1e-6 * mahalanobis);
	}
}

TEST(FactorInformation, SigmaAndSqrtInformation)
{
	auto f = make_factor();
	const double xv[2] = {0.5, -1.5};
	const double* x[1] = {xv};
	Eigen::Vector3d r, rw;
	ASSERT_TRUE(f.evaluate(x, r.data(), nullptr));
	f.set_sigma(0.25);
	ASSERT_TRUE(f.evaluate_whitened(x, rw.data(), nullptr));
	for (int i = 0; i < 3; i++) EXPECT_DOUBLE_EQ(rw[i], r[i] / 0.25);
	Eigen::Matrix3d W;
	W << 1.0, 2.0, 0.0, 0.0, 3.0, -1.0, 0.5, 0.0, 1.0;
	f.set_sqrt_information(W);
	ASSERT_TRUE(f.evaluate_whitened(x, rw.data(), nullptr));
	EXPECT_LE((rw - W * r).cwiseAbs().maxCoeff(), 1e-14);
}

// Whitening multiplies by each row's non-zero span only: lower and upper triangular, banded with a zero
// inside the span, a zero row and a row whose only entry is in the last column all give W·r and W·J.
TEST(FactorInformation, WhiteningOverEachRowsNonZeroSpanIsTheFullProduct)
{
	auto f = make_factor();
	const double xv[2] = {0.7, -1.3};
	Eigen::Matrix3d lower, upper, banded, zero_row, last_only;
	lower << 2.0, 0.0, 0.0, -1.0, 3.0, 0.0, 0.5, 0.25, 1.5;
	upper = lower.transpose();
	banded << 1.0, 0.0, 2.0, 0.0, 3.0, 0.0, 4.0, 0.0, -1.0;
	zero_row << 1.0, 2.0, 3.0, 0.0, 0.0, 0.0, 4.0, 5.0, 6.0;
	last_only << 0.0, 0.0, 2.0, 1.0, 0.0, 0.0, 0.0, 3.0, 0.0;
	for (const Eigen::Matrix3d& W : {lower, upper, banded, zero_row, last_only})
	{
		f.set_sqrt_information(W);
		const Evaluation e = evaluate_both(f, xv);
		EXPECT_LE((e.rw - W * e.r).cwiseAbs().maxCoeff(), 1e-14) << W;
		EXPECT_LE((e.Jw - W * e.J).cwiseAbs().maxCoeff(), 1e-14) << W;
	}
}
