/** \file robust_loss.h
 * The robust loss an application applies to every factor, as a typed option (kind + scale), shared by
 * the options of `swba bal` and `swba pgo`. */
#pragma once

#include <swba/core/loss.h>

#include <memory>
#include <string>

namespace swba::apps
{
enum class RobustLoss
{
	None,    ///< plain least squares
	Huber,   ///< swba::HuberLoss
	Cauchy   ///< swba::CauchyLoss
};

/** Parses "none" (or ""), "huber", "cauchy"; throws std::invalid_argument otherwise (the message of
 * swba::make_loss). */
RobustLoss parse_robust_loss(const std::string& name);
std::string to_string(RobustLoss loss);

/** The loss function (null for None) with scale `scale`, in the unit of the whitened residuals.
 * Throws std::invalid_argument when the scale is not > 0 for Huber or Cauchy. */
std::shared_ptr<const LossFunction> make_robust_loss(RobustLoss loss, double scale);

/** False, with the reason in `why`, when make_robust_loss(loss, scale) would throw. */
bool robust_loss_is_valid(RobustLoss loss, double scale, std::string* why);
}  // namespace swba::apps
