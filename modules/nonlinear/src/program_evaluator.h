// Internal: evaluation of a Program's factors at the current values (Ceres's ProgramEvaluator):
// whitened, loss-corrected residuals and Jacobians into flat buffers, per-factor cost and validity,
// in parallel over factors.
#pragma once

#include "program.h"

#include <vector>

namespace swba::detail
{
/** Below this many items a loop runs on one thread: thread start-up and barriers cost more. */
constexpr int kParallelMin = 2000;

class ProgramEvaluator
{
   public:
	ProgramEvaluator(const Program& program, int num_threads);

	/** Evaluates every factor at the current values; with `jacobians` also the Jacobians.
	 * Returns the total cost; `dropped` receives the count of unevaluable factors and
	 * `newly_dropped` (optional) those that were evaluable at the previous evaluation but are not now.
	 * An unevaluable factor gets zero residual and cost (and zero Jacobians when they are evaluated). */
	double evaluate(bool jacobians, int* dropped, int* newly_dropped = nullptr);

	/** Results of the last evaluation: factor f's residual (m doubles), its row-major m × t Jacobian
	 * block of slot s (non-constant slots only), and whether it could be evaluated. */
	const double* residual(int f) const { return residuals_.data() + program_.factor(f).residual_offset; }
	const double* jacobian(int f, int s) const { return jacobians_.data() + program_.factor(f).jacobian_offset[s]; }
	bool valid(int f) const { return valid_[f] != 0; }

   private:
	/** Evaluates factor f into its slots and sets valid_[f] and factor_cost_[f]. */
	void evaluate_factor(int f, bool want_jacobians);

	const Program& program_;
	int num_threads_;
	std::vector<double> residuals_, jacobians_;
	std::vector<char> valid_, valid_before_;
	std::vector<double> factor_cost_;
};
}  // namespace swba::detail
