// Internal: evaluation of a Program's factors at the current values (Ceres's ProgramEvaluator):
// whitened, loss-corrected residuals and Jacobians into flat buffers, per-factor cost and validity,
// in parallel over factors. The last linearisation (residuals, Jacobians, costs, validity at x) is
// kept apart from a trial evaluation at x ⊞ δ, so that a rejected step leaves it intact and the
// trial can be compared with it factor by factor.
#pragma once

#include "program.h"

#include <vector>

namespace swba::detail
{
/** Below this many items a loop runs on one thread: thread start-up and barriers cost more. */
constexpr int kParallelMin = 2000;

/** A trial point x⁺ compared with the linearisation point x: which factors changed domain
 * (evaluable at one point only) and what they cost where they are evaluable. */
struct TrialEvaluation
{
	double cost = 0;          ///< ½Σρ over the factors evaluable at x⁺
	int dropped = 0;          ///< factors not evaluable at x⁺
	std::vector<int> left;    ///< factors evaluable at x and not at x⁺ (ascending)
	double left_cost = 0;     ///< their cost at x
	int entered = 0;          ///< factors not evaluable at x and evaluable at x⁺
	double entered_cost = 0;  ///< their cost at x⁺
	int stranded = 0;         ///< non-constant variables with an evaluable factor at x and none at x⁺
};

class ProgramEvaluator
{
   public:
	ProgramEvaluator(const Program& program, int num_threads);

	/** Evaluates every factor and its Jacobians at the current values, which become the
	 * linearisation point. Returns the total cost; `dropped` receives the count of unevaluable
	 * factors. An unevaluable factor gets zero residual, cost and Jacobians. */
	double linearize(int* dropped);
	/** Evaluates the costs at the current values (the trial point) without touching the
	 * linearisation, and compares the evaluable sets of the two points. */
	TrialEvaluation evaluate_trial();

	/** The last linearisation: factor f's residual (m doubles), its row-major m × t Jacobian block of
	 * slot s (non-constant slots only), whether it could be evaluated, and its cost. */
	const double* residual(int f) const { return residuals_.data() + program_.factor(f).residual_offset; }
	const double* jacobian(int f, int s) const { return jacobians_.data() + program_.factor(f).jacobian_offset[s]; }
	bool valid(int f) const { return valid_[f] != 0; }
	/** Non-constant variables none of whose factors was evaluable at the last linearisation
	 * (a variable with no factor at all included): the solve cannot move them. */
	int count_unconstrained() const;

   private:
	/** One evaluation's outputs: residual buffer, validity and cost per factor. */
	struct Outputs
	{
		std::vector<double>* residuals;
		std::vector<char>* valid;
		std::vector<double>* cost;
	};
	/** Evaluates factor f into `out` (Jacobians into the linearisation buffer when requested). */
	void evaluate_factor(int f, bool want_jacobians, const Outputs& out);
	/** Evaluates every factor into `out`; returns the total cost and the number not evaluable. */
	double evaluate_all(bool want_jacobians, const Outputs& out, int* dropped);
	/** Variables of the `left` factors with no factor evaluable at the trial point. */
	int count_stranded(const std::vector<int>& left) const;

	const Program& program_;
	int num_threads_;
	std::vector<double> residuals_, jacobians_, factor_cost_;
	std::vector<char> valid_;
	std::vector<double> trial_residuals_, trial_cost_;
	std::vector<char> trial_valid_;
};
}  // namespace swba::detail
