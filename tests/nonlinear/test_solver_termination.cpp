// When LM stops after a rejected step (solver.h, SolverOptions::function_tolerance): at the minimum its
// model can see, where only a Jacobian that is not the cost's own moves the cost, it stops at once; after
// an overshoot that lands at an equal cost it goes on.
#include <gtest/gtest.h>
#include <swba/nonlinear/solver.h>

#include <cmath>
#include <string>

using namespace swba;

namespace
{
/** r = x − b on a 1-D variable, with a reported Jacobian `slope` that need not be 1 (as a first-estimate
 * Jacobian is not the derivative at the current value). */
class ReportedSlopeFactor final : public Factor
{
   public:
	ReportedSlopeFactor(double b, double slope) : Factor(1, {1}), b_(b), slope_(slope) {}
	bool evaluate(const double* const* x, double* r, double* const* jac) const override
	{
		r[0] = x[0][0] - b_;
		if (jac && jac[0]) jac[0][0] = slope_;
		return true;
	}

   private:
	double b_, slope_;
};

struct SlopeProblem
{
	Problem problem;
	VariableId x;
};

SlopeProblem make_slope_problem(double x0)
{
	SlopeProblem p;
	p.x = p.problem.add_variable(&x0, euclidean_manifold(1));
	return p;
}

int rejected_steps(const Summary& s)
{
	int n = 0;
	for (const IterationSummary& it : s.iterations_log) n += it.iteration > 0 && !it.step_accepted;
	return n;
}
}  // namespace

TEST(SolverTermination, RejectedStepAtTheModelsMinimumEndsTheSolve)
{
	// Cost ½x² + ½(x − 1)², minimum at 0.5; the second factor reports slope 2, so the model's minimum
	// (x + 2(x − 1) = 0) is 2/3. LM climbs past 0.5, where every step towards 2/3 raises the cost.
	auto p = make_slope_problem(0.0);
	p.problem.add_factor(std::make_shared<ReportedSlopeFactor>(0.0, 1.0), {p.x});
	p.problem.add_factor(std::make_shared<ReportedSlopeFactor>(1.0, 2.0), {p.x});
	const Summary s = solve(p.problem);
	EXPECT_EQ(s.termination, TerminationType::Convergence);
	EXPECT_EQ(s.message, "function tolerance reached");
	const IterationSummary& last = s.iterations_log.back();
	EXPECT_FALSE(last.step_accepted);
	EXPECT_LE(std::abs(last.cost_change), 1e-6 * s.final_cost);
	EXPECT_LE(last.model_cost_change, 1e-6 * s.final_cost);
	// Without the rule LM shrinks the region until it is below its minimum (1e-32): more rejections.
	EXPECT_LT(rejected_steps(s), 12) << rejected_steps(s) << " rejected steps";
	EXPECT_NEAR(p.problem.value(p.x)[0], 0.5, 0.1);
}

TEST(SolverTermination, OvershootToAnEqualCostDoesNotEndTheSolve)
{
	// r = x with a reported slope of 0.5: the undamped step from x = 1 goes to −1, the same cost, while the
	// model predicted a decrease of ½. That is not convergence; a smaller region reaches the minimum.
	auto p = make_slope_problem(1.0);
	p.problem.add_factor(std::make_shared<ReportedSlopeFactor>(0.0, 0.5), {p.x});
	SolverOptions o;
	o.initial_trust_region_radius = 1e16;  // the first step is the undamped one
	const Summary s = solve(p.problem, o);
	ASSERT_GE(s.iterations_log.size(), 2u);
	EXPECT_FALSE(s.iterations_log[1].step_accepted);
	EXPECT_NEAR(s.iterations_log[1].cost_change, 0.0, 1e-12);
	EXPECT_NEAR(s.iterations_log[1].model_cost_change, 0.5, 1e-6);
	// The solve went on (with this Jacobian LM converges linearly, so it may use all its iterations).
	EXPECT_GT(s.iterations, 2);
	EXPECT_LT(std::abs(p.problem.value(p.x)[0]), 1e-3);
}
