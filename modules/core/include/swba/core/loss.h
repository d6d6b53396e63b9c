/** \file loss.h
 * Robust loss functions ρ(s) of the squared whitened residual norm s = ‖r‖², as in Ceres:
 * cost = ½ ρ(s); the solver applies them through Triggs' correction (see apply_loss). */
#pragma once

#include <swba/core/names.h>

#include <array>
#include <memory>
#include <string>

namespace swba
{
class LossFunction
{
   public:
	virtual ~LossFunction() = default;
	/** rho[0] = ρ(s), rho[1] = ρ'(s), rho[2] = ρ''(s). */
	virtual void evaluate(double s, double rho[3]) const = 0;
};

/** ρ(s) = s for s ≤ a², 2a√s − a² otherwise (a = scale, in whitened residual units). */
class HuberLoss final : public LossFunction
{
   public:
	explicit HuberLoss(double a);
	void evaluate(double s, double rho[3]) const override;

   private:
	double a_, b_;
};

/** ρ(s) = a² log(1 + s/a²). */
class CauchyLoss final : public LossFunction
{
   public:
	explicit CauchyLoss(double a);
	void evaluate(double s, double rho[3]) const override;

   private:
	double b_, c_;
};

/** The robust losses by kind, as an option value. */
enum class RobustLoss
{
	None,   ///< plain least squares (no loss object)
	Huber,  ///< HuberLoss
	Cauchy  ///< CauchyLoss
};
constexpr std::array<EnumName<RobustLoss>, 4> enum_names(RobustLoss)
{
	return {{{RobustLoss::None, "none"},
			 {RobustLoss::Huber, "huber"},
			 {RobustLoss::Cauchy, "cauchy"},
			 {RobustLoss::None, "", true}}};
}

/** The loss of kind `kind` with scale `a` (in whitened residual units); nullptr for None. Throws
 * std::invalid_argument when a is not > 0 for Huber or Cauchy. */
std::shared_ptr<const LossFunction> make_loss(RobustLoss kind, double a);
/** make_loss(parse_enum<RobustLoss>(name, "loss"), a): "none" (or ""), "huber", "cauchy". */
std::shared_ptr<const LossFunction> make_loss(const std::string& name, double a);

/** Applies a loss to a whitened residual r (dim m) and its Jacobian blocks as Ceres's Corrector does,
 * so that ½‖r̃‖² and J̃ᵀJ̃ give the robustified cost's gradient and Gauss-Newton Hessian.
 * `jac_cols[i]` columns for block i (row-major m × jac_cols[i]); `jacobians` may be null (residual
 * only) and null blocks are skipped.
 * Returns ½ρ(‖r‖²). */
double apply_loss(const LossFunction& loss, int m, double* r, int num_blocks, const int* jac_cols,
				  double* const* jacobians);
}  // namespace swba
