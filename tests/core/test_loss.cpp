// Robust losses: values and derivatives against central differences, and the Ceres-like correction
// of apply_loss (J̃ᵀr̃ = ρ'Jᵀr, the gradient of ½ρ(‖r‖²); J̃ᵀJ̃ = Jᵀ(ρ'I + 2ρ''rrᵀ)J when ρ'' > 0).
#include <swba/core/loss.h>

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <random>
#include <vector>

namespace
{
using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/** ρ(s) = s + c·s², convex (ρ'' > 0): exercises the α branch of the correction that Huber and
 * Cauchy (ρ'' ≤ 0) never reach. Test-only. */
class QuadraticTestLoss final : public swba::LossFunction
{
   public:
	explicit QuadraticTestLoss(double c) : c_(c) {}
	void evaluate(double s, double rho[3]) const override
	{
		rho[0] = s + c_ * s * s;
		rho[1] = 1.0 + 2.0 * c_ * s;
		rho[2] = 2.0 * c_;
	}

   private:
	double c_;
};

/** Checks ρ' and ρ'' against central differences of ρ (and of ρ') at s. */
void check_derivatives(const swba::LossFunction& loss, double s)
{
	const double h = 1e-6 * std::max(1.0, s);
	double rp[3], rm[3], r0[3];
	loss.evaluate(s, r0);
	loss.evaluate(s + h, rp);
	loss.evaluate(s - h, rm);
	const double d1 = (rp[0] - rm[0]) / (2 * h);
	const double d2 = (rp[1] - rm[1]) / (2 * h);
	EXPECT_NEAR(r0[1], d1, 1e-7 * std::max(1.0, std::abs(d1))) << "rho' at s = " << s;
	EXPECT_NEAR(r0[2], d2, 1e-6 * std::max(1.0, std::abs(d2))) << "rho'' at s = " << s;
}
}  // namespace

TEST(Loss, HuberValuesAndDerivatives)
{
	const double a = 1.5;
	const swba::HuberLoss loss(a);
	double rho[3];
	// Quadratic region: ρ = s exactly.
	loss.evaluate(1.0, rho);
	EXPECT_DOUBLE_EQ(rho[0], 1.0);
	EXPECT_DOUBLE_EQ(rho[1], 1.0);
	EXPECT_DOUBLE_EQ(rho[2], 0.0);
	// Linear region: ρ = 2a√s − a².
	loss.evaluate(16.0, rho);
	EXPECT_DOUBLE_EQ(rho[0], 2 * a * 4.0 - a * a);
	EXPECT_DOUBLE_EQ(rho[1], a / 4.0);
	EXPECT_DOUBLE_EQ(rho[2], -(a / 4.0) / 32.0);
	// Continuity of ρ and ρ' at the knee s = a².
	double lo[3], hi[3];
	loss.evaluate(a * a * (1 - 1e-12), lo);
	loss.evaluate(a * a * (1 + 1e-12), hi);
	EXPECT_NEAR(lo[0], hi[0], 1e-10);
	EXPECT_NEAR(lo[1], hi[1], 1e-10);
	for (double s : {1e-6, 0.3, 2.0, 2.2, 2.3, 10.0, 1e4}) check_derivatives(loss, s);
	EXPECT_THROW(swba::HuberLoss(0.0), std::invalid_argument);
	EXPECT_THROW(swba::HuberLoss(-1.0), std::invalid_argument);
}

TEST(Loss, CauchyValuesAndDerivatives)
{
	const double a = 2.0;
	const swba::CauchyLoss loss(a);
	double rho[3];
	for (double s : {0.0, 0.5, 4.0, 100.0})
	{
		loss.evaluate(s, rho);
		EXPECT_NEAR(rho[0], a * a * std::log(1 + s / (a * a)), 1e-14 * std::max(1.0, rho[0]));
		EXPECT_NEAR(rho[1], 1.0 / (1 + s / (a * a)), 1e-15);
	}
	loss.evaluate(0.0, rho);
	EXPECT_EQ(rho[0], 0.0);
	EXPECT_EQ(rho[1], 1.0);
	for (double s : {1e-6, 0.3, 2.0, 10.0, 1e4}) check_derivatives(loss, s);
	EXPECT_THROW(swba::CauchyLoss(0.0), std::invalid_argument);
}

TEST(Loss, MakeLoss)
{
	EXPECT_EQ(swba::make_loss("none", 1.0), nullptr);
	EXPECT_NE(dynamic_cast<const swba::HuberLoss*>(swba::make_loss("huber", 1.0).get()), nullptr);
	EXPECT_NE(dynamic_cast<const swba::CauchyLoss*>(swba::make_loss("cauchy", 1.0).get()), nullptr);
	EXPECT_THROW(swba::make_loss("tukey", 1.0), std::invalid_argument);
	EXPECT_THROW(swba::make_loss("huber", 0.0), std::invalid_argument);
}

namespace
{
struct Corrected
{
	Eigen::VectorXd r;
	RowMatrix J1, J2;
	double cost;
};
Corrected correct(const swba::LossFunction& loss, const Eigen::VectorXd& r, const RowMatrix& J1, const RowMatrix& J2)
{
	Corrected c{r, J1, J2, 0.0};
	const int cols[3] = {static_cast<int>(J1.cols()), 1, static_cast<int>(J2.cols())};
	double* jac[3] = {c.J1.data(), nullptr, c.J2.data()};
	c.cost = swba::apply_loss(loss, static_cast<int>(r.size()), c.r.data(), 3, cols, jac);
	return c;
}

/** Numeric gradient of ½ρ(‖r0 + J δ‖²) at δ = 0 (J = [J1 J2]). */
Eigen::VectorXd numeric_gradient(const swba::LossFunction& loss, const Eigen::VectorXd& r0, const RowMatrix& J)
{
	const double h = 1e-6;
	Eigen::VectorXd g(J.cols());
	for (int k = 0; k < J.cols(); k++)
	{
		double rp[3], rm[3];
		loss.evaluate((r0 + h * J.col(k)).squaredNorm(), rp);
		loss.evaluate((r0 - h * J.col(k)).squaredNorm(), rm);
		g[k] = (0.5 * rp[0] - 0.5 * rm[0]) / (2 * h);
	}
	return g;
}
}  // namespace

TEST(Loss, CorrectionGivesRobustGradientAndGaussNewtonHessian)
{
	std::mt19937 rng(3);
	std::normal_distribution<double> g(0.0, 1.0);
	const swba::HuberLoss huber(1.0);
	const swba::CauchyLoss cauchy(0.7);
	const QuadraticTestLoss quad(0.05);
	const std::vector<const swba::LossFunction*> losses = {&huber, &cauchy, &quad};
	const int m = 3;
	for (const auto* loss : losses)
		for (double scale : {0.1, 0.5, 3.0, 20.0})  // inlier and outlier residuals
			for (int trial = 0; trial < 5; trial++)
			{
				Eigen::VectorXd r(m);
				RowMatrix J1(m, 2), J2(m, 4);
				for (int i = 0; i < m; i++) r[i] = scale * g(rng);
				for (int i = 0; i < J1.size(); i++) J1.data()[i] = g(rng);
				for (int i = 0; i < J2.size(); i++) J2.data()[i] = g(rng);
				RowMatrix J(m, 6);
				J << J1, J2;
				const Corrected c = correct(*loss, r, J1, J2);
				double rho[3];
				const double s = r.squaredNorm();
				loss->evaluate(s, rho);
				EXPECT_DOUBLE_EQ(c.cost, 0.5 * rho[0]);
				RowMatrix Jc(m, 6);
				Jc << c.J1, c.J2;
				// Gradient: J̃ᵀr̃ = ρ'Jᵀr, and equal to the numeric gradient of ½ρ(‖r + Jδ‖²).
				const Eigen::VectorXd grad = Jc.transpose() * c.r;
				const Eigen::VectorXd expected = rho[1] * J.transpose() * r;
				EXPECT_LE((grad - expected).cwiseAbs().maxCoeff(), 1e-12 * std::max(1.0, expected.norm()));
				const Eigen::VectorXd num = numeric_gradient(*loss, r, J);
				EXPECT_LE((grad - num).cwiseAbs().maxCoeff(), 1e-6 * std::max(1.0, num.norm()));
				// Hessian: Ceres keeps the second-order term only when ρ'' > 0.
				const Eigen::MatrixXd H = Jc.transpose() * Jc;
				Eigen::MatrixXd H_expected = rho[1] * J.transpose() * J;
				if (rho[2] > 0) H_expected += 2.0 * rho[2] * J.transpose() * r * r.transpose() * J;
				EXPECT_LE((H - H_expected).cwiseAbs().maxCoeff(), 1e-10 * std::max(1.0, H_expected.norm()));
			}
}

TEST(Loss, CorrectionOfAZeroResidualIsHarmless)
{
	const swba::CauchyLoss loss(1.0);
	Eigen::VectorXd r = Eigen::VectorXd::Zero(2);
	RowMatrix J1 = RowMatrix::Ones(2, 3), J2 = RowMatrix::Ones(2, 1);
	const Corrected c = correct(loss, r, J1, J2);
	EXPECT_TRUE(c.r.allFinite());
	EXPECT_TRUE(c.J1.allFinite());
	EXPECT_EQ(c.cost, 0.0);
	EXPECT_EQ((c.J1 - J1).cwiseAbs().maxCoeff(), 0.0);  // ρ'(0) = 1
}
