#include <swba/core/loss.h>

#include <cmath>
#include <stdexcept>

namespace swba
{
HuberLoss::HuberLoss(double a) : a_(a), b_(a * a)
{
	if (!(a > 0)) throw std::invalid_argument("HuberLoss: scale must be > 0");
}

void HuberLoss::evaluate(double s, double rho[3]) const
{
	if (s > b_)
	{
		const double r = std::sqrt(s);
		rho[0] = 2.0 * a_ * r - b_;
		rho[1] = std::max(a_ / r, 1e-300);
		rho[2] = -rho[1] / (2.0 * s);
	}
	else
	{
		rho[0] = s;
		rho[1] = 1.0;
		rho[2] = 0.0;
	}
}

CauchyLoss::CauchyLoss(double a) : b_(a * a), c_(1.0 / (a * a))
{
	if (!(a > 0)) throw std::invalid_argument("CauchyLoss: scale must be > 0");
}

void CauchyLoss::evaluate(double s, double rho[3]) const
{
	const double sum = 1.0 + s * c_;
	const double inv = 1.0 / sum;
	rho[0] = b_ * std::log1p(s * c_);
	rho[1] = std::max(inv, 1e-300);
	rho[2] = -c_ * (inv * inv);
}

std::shared_ptr<const LossFunction> make_loss(RobustLoss kind, double a)
{
	switch (kind)
	{
		case RobustLoss::None: return nullptr;
		case RobustLoss::Huber: return std::make_shared<HuberLoss>(a);
		case RobustLoss::Cauchy: return std::make_shared<CauchyLoss>(a);
	}
	throw std::logic_error("unknown RobustLoss value");
}

std::shared_ptr<const LossFunction> make_loss(const std::string& name, double a)
{
	return make_loss(parse_enum<RobustLoss>(name, "loss"), a);
}

double apply_loss(const LossFunction& loss, int m, double* r, int num_blocks, const int* jac_cols,
				  double* const* jacobians)
{
	double s = 0;
	for (int i = 0; i < m; i++) s += r[i] * r[i];
	double rho[3];
	loss.evaluate(s, rho);
	// Triggs correction (Ceres corrector.cc): r̃ = √ρ' r / (1-α), J̃ = √ρ' (I - α r rᵀ/‖r‖²) J,
	// with α the root of ½α² - α - ρ''/ρ' ‖r‖² = 0 that is ≤ 1.
	const double sqrt_rho1 = std::sqrt(rho[1]);
	double residual_scaling, alpha_sq_norm;
	if (s == 0.0 || rho[2] <= 0.0)
	{
		residual_scaling = sqrt_rho1;
		alpha_sq_norm = 0.0;
	}
	else
	{
		const double D = 1.0 + 2.0 * s * rho[2] / rho[1];
		const double alpha = 1.0 - std::sqrt(std::max(D, 0.0));
		residual_scaling = sqrt_rho1 / (1.0 - alpha);
		alpha_sq_norm = alpha / s;
	}
	for (int b = 0; jacobians && b < num_blocks; b++)
	{
		double* J = jacobians[b];
		if (!J) continue;
		const int n = jac_cols[b];
		if (alpha_sq_norm == 0.0)
		{
			for (int k = 0; k < m * n; k++) J[k] *= sqrt_rho1;
			continue;
		}
		for (int c = 0; c < n; c++)
		{
			double rtJ = 0;
			for (int i = 0; i < m; i++) rtJ += r[i] * J[i * n + c];
			for (int i = 0; i < m; i++)
				J[i * n + c] = sqrt_rho1 * (J[i * n + c] - alpha_sq_norm * r[i] * rtJ);
		}
	}
	for (int i = 0; i < m; i++) r[i] *= residual_scaling;
	return 0.5 * rho[0];
}
}  // namespace swba
