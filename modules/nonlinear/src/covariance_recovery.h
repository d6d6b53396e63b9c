// Internal: covariance recovery on a SolverContext whose normal equations are assembled at the
// current values (after a solve's last linearisation, or a fresh one).
#pragma once

#include <swba/nonlinear/covariance.h>

namespace swba::detail
{
class SolverContext;

/** Factorises the undamped system of `context` (replacing its damped factorisation) and recovers the
 * blocks of `request` (covariance.h). */
CovarianceResult recover_covariance(SolverContext& context, const CovarianceRequest& request);
}  // namespace swba::detail
