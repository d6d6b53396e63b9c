// Tests of the IMU pre-integration: closed forms on constant-rate motion, the order of the midpoint
// scheme, the bias Jacobians against re-integration, and the propagated covariance against Monte Carlo.
#include "factor_test_fixtures.h"

#include <swba/core/lie.h>
#include <swba/factors/imu_preintegration.h>

#include <random>

using namespace swba;
using namespace swba::factor_test;

namespace
{
/** Readings of a body turning at constant rate ω with constant specific force a (body), from 0 to T. */
ImuPreintegration constant_rate(const Eigen::Vector3d& w, const Eigen::Vector3d& a, double T, int steps)
{
	ImuPreintegration pim(ImuNoise{}, Vector6d::Zero());
	for (int k = 0; k <= steps; k++) pim.add_sample({T * k / steps, a, w});
	return pim;
}

/** ∫₀ᵀ Exp(ωs) ds and ∫₀ᵀ∫₀ˢ Exp(ωu) du ds in closed form (θ = ‖ω‖, W the skew matrix of the unit axis). */
void closed_form(const Eigen::Vector3d& w, double T, Eigen::Matrix3d& S1, Eigen::Matrix3d& S2)
{
	const double th = w.norm();
	const Eigen::Matrix3d W = skew(w / th), W2 = W * W, I = Eigen::Matrix3d::Identity();
	S1 = T * I + (1 - std::cos(th * T)) / th * W + (T - std::sin(th * T) / th) * W2;
	S2 = 0.5 * T * T * I + (T / th - std::sin(th * T) / (th * th)) * W +
		 (0.5 * T * T - (1 - std::cos(th * T)) / (th * th)) * W2;
}

/** Random smooth-ish readings: `n` samples at `rate` Hz around a turning, accelerating body. */
std::vector<ImuSample> random_readings(Rng& rng, int n, double rate)
{
	const Eigen::Vector3d w0 = rng.vec(-1, 1), w1 = rng.vec(-0.5, 0.5), a0 = rng.vec(-3, 3) + Eigen::Vector3d(0, 0, 9.8),
						  a1 = rng.vec(-2, 2);
	std::vector<ImuSample> out;
	for (int k = 0; k < n; k++)
	{
		const double t = k / rate;
		out.push_back({t, a0 + a1 * std::sin(3 * t), w0 + w1 * std::cos(2 * t)});
	}
	return out;
}

ImuPreintegration integrate(const std::vector<ImuSample>& s, const Vector6d& bias, const ImuNoise& noise = {})
{
	ImuPreintegration pim(noise, bias);
	for (const auto& x : s) pim.add_sample(x);
	return pim;
}

/** Central differences of the deltas [Δp, Δφ, Δv] w.r.t. the bias, by re-integration at b ± h. */
Eigen::Matrix<double, 9, 6> numeric_bias_jacobian(const std::vector<ImuSample>& s, const Vector6d& b)
{
	Eigen::Matrix<double, 9, 6> N;
	const double h = 1e-5;
	for (int c = 0; c < 6; c++)
	{
		Vector6d bp = b, bm = b;
		bp[c] += h;
		bm[c] -= h;
		const ImuPreintegration P = integrate(s, bp), M = integrate(s, bm);
		N.block<3, 1>(0, c) = (P.delta_p() - M.delta_p()) / (2 * h);
		N.block<3, 1>(3, c) = so3_log(M.delta_R().transpose() * P.delta_R()) / (2 * h);
		N.block<3, 1>(6, c) = (P.delta_v() - M.delta_v()) / (2 * h);
	}
	return N;
}
}  // namespace

TEST(ImuPreintegration, ConstantRateMatchesClosedFormToSecondOrder)
{
	const Eigen::Vector3d w(0.3, -0.5, 0.8), a(1.0, -2.0, 9.81);
	const double T = 1.0;
	Eigen::Matrix3d S1, S2;
	closed_form(w, T, S1, S2);
	const Eigen::Vector3d v_exact = S1 * a, p_exact = S2 * a;
	double err_prev_v = 0, err_prev_p = 0;
	for (int steps : {100, 200, 400})
	{
		const ImuPreintegration pim = constant_rate(w, a, T, steps);
		EXPECT_NEAR(pim.delta_t(), T, 1e-12);
		EXPECT_LT(so3_log(pim.delta_R().transpose() * so3_exp(w * T)).norm(), 1e-12);
		const double ev = (pim.delta_v() - v_exact).norm(), ep = (pim.delta_p() - p_exact).norm();
		EXPECT_LT(ev, 2e-4 * (100.0 / steps) * (100.0 / steps)) << steps;
		EXPECT_LT(ep, 2e-4 * (100.0 / steps) * (100.0 / steps)) << steps;
		if (err_prev_v > 0)
		{
			// Midpoint: the error falls by 4 when the step halves (Euler would give 2).
			EXPECT_NEAR(err_prev_v / ev, 4.0, 0.2) << steps;
			EXPECT_NEAR(err_prev_p / ep, 4.0, 0.2) << steps;
		}
		err_prev_v = ev;
		err_prev_p = ep;
	}
}

TEST(ImuPreintegration, ConstantAccelerationWithoutRotationIsExact)
{
	const Eigen::Vector3d a(0.5, -1.5, 9.0);
	const ImuPreintegration pim = constant_rate(Eigen::Vector3d::Zero(), a, 2.0, 37);
	EXPECT_LT((pim.delta_v() - 2.0 * a).norm(), 1e-12);
	EXPECT_LT((pim.delta_p() - 2.0 * a).norm(), 1e-12);  // ½ a T² with T = 2
	EXPECT_LT((pim.delta_R() - Eigen::Matrix3d::Identity()).norm(), 1e-15);
}

TEST(ImuPreintegration, PredictionMatchesMidpointNavigation)
{
	Rng rng(7);
	const auto s = random_readings(rng, 81, 200.0);
	Vector6d b;
	b << rng.vec(-0.1, 0.1), rng.vec(-0.01, 0.01);
	const ImuPreintegration pim = integrate(s, b);
	NavState x0;
	x0.R = rng.rotation();
	x0.p = rng.vec(-5, 5);
	x0.v = rng.vec(-2, 2);
	NavState x = x0;
	for (size_t k = 1; k < s.size(); k++) x = imu_midpoint_step(x, s[k - 1], s[k], b, pim.noise().gravity);
	const NavState y = pim.predict(x0, b);
	EXPECT_LT((x.p - y.p).norm(), 1e-10);
	EXPECT_LT((x.v - y.v).norm(), 1e-10);
	EXPECT_LT(so3_log(x.R.transpose() * y.R).norm(), 1e-10);
}

TEST(ImuPreintegration, BiasJacobiansMatchReintegration)
{
	for (unsigned seed : {1u, 2u, 3u})
	{
		Rng rng(seed);
		const auto s = random_readings(rng, 101, 200.0);
		Vector6d b;
		b << rng.vec(-0.2, 0.2), rng.vec(-0.02, 0.02);
		const ImuPreintegration pim = integrate(s, b);
		const Eigen::Matrix<double, 9, 6> N = numeric_bias_jacobian(s, b);
		const double scale = std::max(1.0, N.cwiseAbs().maxCoeff());
		const double err = (N - pim.bias_jacobian()).cwiseAbs().maxCoeff() / scale;
		EXPECT_LT(err, 1e-6) << "seed " << seed << "\nanalytic\n" << pim.bias_jacobian() << "\nnumeric\n" << N;
		EXPECT_LT((pim.bias_jacobian().block<3, 3>(3, 0).norm()), 1e-15);  // ΔR does not depend on b_a
	}
}

TEST(ImuPreintegration, WhiteNoiseEntersAStepAsTheBiasDoes)
{
	// A reading's white noise shifts the step as a bias error does (ω = ω̃ − b_g − n_g, a = ã − b_a − n_a):
	// the noise columns of G are the one-step derivatives of the deltas w.r.t. the bias, second-order terms
	// (the gyroscope noise into Δp and Δv through the second reading's rotation, M_g) included.
	for (unsigned seed : {4u, 5u})
	{
		Rng rng(seed);
		const auto s = random_readings(rng, 2, 100.0);
		Vector6d b;
		b << rng.vec(-0.2, 0.2), rng.vec(-0.02, 0.02);
		const MidpointLinearization L = midpoint_linearization(Eigen::Matrix3d::Identity(), s[0], s[1], b);
		const Eigen::Matrix<double, 9, 6> N = numeric_bias_jacobian(s, b);
		EXPECT_LT((L.G.topLeftCorner<9, 6>() - N).cwiseAbs().maxCoeff(), 1e-9) << "G\n" << L.G.topLeftCorner<9, 6>() << "\nnumeric\n" << N;
	}
}

TEST(ImuPreintegration, FirstOrderBiasUpdateApproximatesReintegration)
{
	Rng rng(11);
	const auto s = random_readings(rng, 201, 200.0);
	const Vector6d b0 = Vector6d::Zero();
	Vector6d db;
	db << 0.05, -0.03, 0.04, 0.004, -0.006, 0.003;
	const ImuPreintegration pim = integrate(s, b0), re = integrate(s, b0 + db);
	// The correction's own size and what is left after it: second order in δb.
	const double move_p = (re.delta_p() - pim.delta_p()).norm(), left_p = (re.delta_p() - pim.corrected_delta_p(b0 + db)).norm();
	const double move_v = (re.delta_v() - pim.delta_v()).norm(), left_v = (re.delta_v() - pim.corrected_delta_v(b0 + db)).norm();
	const double move_R = so3_log(pim.delta_R().transpose() * re.delta_R()).norm(),
				 left_R = so3_log(pim.corrected_delta_R(b0 + db).transpose() * re.delta_R()).norm();
	EXPECT_LT(left_p, 0.01 * move_p);
	EXPECT_LT(left_v, 0.01 * move_v);
	EXPECT_LT(left_R, 0.01 * move_R);
	// Re-integrating at b0 + δb moves the linearisation bias and reproduces the direct integration.
	ImuPreintegration again = pim;
	again.reintegrate(b0 + db);
	EXPECT_LT((again.delta_p() - re.delta_p()).norm(), 1e-14);
	EXPECT_TRUE(pim.bias_far(b0 + db, 0.01, 0.001));
	EXPECT_FALSE(pim.bias_far(b0 + 0.1 * db, 0.01, 0.001));
	// Far is either sensor's bias on any one axis.
	for (int c = 0; c < 6; c++)
	{
		Vector6d moved = b0;
		moved[c] += c < 3 ? 0.011 : 0.0011;
		EXPECT_TRUE(pim.bias_far(moved, 0.01, 0.001)) << "axis " << c;
		moved[c] = b0[c] + (c < 3 ? 0.009 : 0.0009);
		EXPECT_FALSE(pim.bias_far(moved, 0.01, 0.001)) << "axis " << c;
	}
}

namespace
{
/** Monte-Carlo covariance of the factor's residual at the true states ([Δp, Δφ, Δv, b_j − b_i], with
 * b_i = b̄ the true bias at t_i): readings with white noise σ/√Δt per sample and a bias that random-walks
 * by σ_b√Δt per sample, integrated at b̄. */
Matrix15d monte_carlo_covariance(const std::vector<ImuSample>& s, const ImuNoise& n, int runs)
{
	const ImuPreintegration clean = integrate(s, Vector6d::Zero(), n);
	std::mt19937 gen(5);
	std::normal_distribution<double> N01;
	auto noise3 = [&](double sd) -> Eigen::Vector3d { return Eigen::Vector3d(N01(gen), N01(gen), N01(gen)) * sd; };
	const double dt = s[1].t - s[0].t;
	Matrix15d C = Matrix15d::Zero();
	for (int r = 0; r < runs; r++)
	{
		ImuPreintegration noisy(n, Vector6d::Zero());
		Vector6d bias = Vector6d::Zero();
		for (size_t k = 0; k < s.size(); k++)
		{
			if (k > 0) bias += (Vector6d() << noise3(n.accel_random_walk * std::sqrt(dt)), noise3(n.gyro_random_walk * std::sqrt(dt))).finished();
			ImuSample x = s[k];
			x.acc += bias.head<3>() + noise3(n.accel_noise_density / std::sqrt(dt));
			x.gyro += bias.tail<3>() + noise3(n.gyro_noise_density / std::sqrt(dt));
			noisy.add_sample(x);
		}
		Eigen::Matrix<double, 15, 1> e;
		e << clean.delta_p() - noisy.delta_p(), so3_log(noisy.delta_R().transpose() * clean.delta_R()),
			clean.delta_v() - noisy.delta_v(), bias;
		C += e * e.transpose();
	}
	return C / runs;
}

void expect_covariance_close(const Matrix15d& model, const Matrix15d& mc, const std::string& what)
{
	for (int i = 0; i < 15; i++)
	{
		EXPECT_NEAR(mc(i, i) / model(i, i), 1.0, 0.15) << what << " diagonal " << i;
		for (int j = 0; j < i; j++)
		{
			const double scale = std::sqrt(model(i, i) * model(j, j));
			EXPECT_NEAR(mc(i, j) / scale, model(i, j) / scale, 0.1) << what << " entry " << i << "," << j;
		}
	}
}
}  // namespace

TEST(ImuPreintegration, CovarianceMatchesMonteCarlo)
{
	Rng rng(3);
	const auto s = random_readings(rng, 101, 200.0);
	ImuNoise white;  // white noise dominates the deltas
	white.accel_noise_density = 0.05;
	white.gyro_noise_density = 0.01;
	white.accel_random_walk = 1e-3;
	white.gyro_random_walk = 1e-4;
	expect_covariance_close(integrate(s, Vector6d::Zero(), white).covariance(), monte_carlo_covariance(s, white, 3000),
							"white-noise dominated");
	ImuNoise walk;  // the bias random walk dominates: checks the bias columns of the transition
	walk.accel_noise_density = 1e-3;
	walk.gyro_noise_density = 1e-4;
	walk.accel_random_walk = 0.5;
	walk.gyro_random_walk = 0.05;
	expect_covariance_close(integrate(s, Vector6d::Zero(), walk).covariance(), monte_carlo_covariance(s, walk, 3000),
							"random-walk dominated");
}
