// The LM step rule when factors cannot be evaluated everywhere (solver.h): a step is judged on the
// factors evaluable before and after it, a factor leaving its domain is neither credited nor charged,
// such a step does not enlarge the trust region, and the log says why a step was rejected.
#include <gtest/gtest.h>
#include <swba/nonlinear/solver.h>

#include <algorithm>
#include <cmath>

using namespace swba;

namespace
{
/** r = a·(x − b) on a 1-D variable x; with `limit`, evaluable only while x < limit (as a patch that
 * exists only inside its image). The optional second variable y is connected but not used: a factor
 * is its only one, so y loses its last factor when this one leaves its domain. */
class LineFactor final : public Factor
{
   public:
	LineFactor(double a, double b, double limit = INFINITY, bool with_y = false)
		: Factor(1, with_y ? std::vector<int>{1, 1} : std::vector<int>{1}), a_(a), b_(b), limit_(limit)
	{
	}
	bool evaluate(const double* const* x, double* r, double* const* jac) const override
	{
		if (!(x[0][0] < limit_)) return false;
		r[0] = a_ * (x[0][0] - b_);
		if (jac && jac[0]) jac[0][0] = a_;
		if (num_variables() == 2 && jac && jac[1]) jac[1][0] = 0.0;
		return true;
	}

   private:
	double a_, b_, limit_;
};

/** r = x² − 4: Gauss-Newton from near 0 overshoots far past the root. */
class SquareFactor final : public Factor
{
   public:
	SquareFactor() : Factor(1, {1}) {}
	bool evaluate(const double* const* x, double* r, double* const* jac) const override
	{
		r[0] = x[0][0] * x[0][0] - 4.0;
		if (jac && jac[0]) jac[0][0] = 2.0 * x[0][0];
		return true;
	}
};

struct LineProblem
{
	Problem problem;
	VariableId x, y;
};

/** A: r = x − a_target (always evaluable); B: r = 0.5·(x − 4), evaluable while x < 5, on (x, y). */
LineProblem make_line_problem(double x0, double a_target)
{
	LineProblem p;
	const double zero = 0.0;
	p.x = p.problem.add_variable(&x0, euclidean_manifold(1));
	p.y = p.problem.add_variable(&zero, euclidean_manifold(1));
	p.problem.add_factor(std::make_shared<LineFactor>(1.0, a_target), {p.x});
	p.problem.add_factor(std::make_shared<LineFactor>(0.5, 4.0, 5.0, true), {p.x, p.y});
	return p;
}

double cost_a(double x, double target) { return 0.5 * (x - target) * (x - target); }
double cost_b(double x) { return 0.5 * 0.25 * (x - 4.0) * (x - 4.0); }

/** Solves `p`; its first step (iterations_log[1], present even when the solve took none) must be
 * accepted with the given counts of factors that left / entered their domain and stranded variables. */
Summary solve_with_accepted_first_step(LineProblem& p, int left, int entered, int stranded)
{
	Summary s = solve(p.problem);
	if (s.iterations_log.size() < 2) ADD_FAILURE() << "no LM step was taken";
	s.iterations_log.resize(std::max<size_t>(2, s.iterations_log.size()));
	EXPECT_TRUE(s.iterations_log[1].step_accepted);
	EXPECT_EQ(s.iterations_log[1].outcome, StepOutcome::Accepted);
	EXPECT_EQ(s.iterations_log[1].factors_left, left);
	EXPECT_EQ(s.iterations_log[1].factors_entered, entered);
	EXPECT_EQ(s.iterations_log[1].variables_stranded, stranded);
	return s;
}
}  // namespace

TEST(SolverDomain, StepTakingAFactorOutOfItsDomainIsJudgedOnTheFactorsEvaluableAtBothPoints)
{
	// From x = 0 the first step goes to ≈ 8.8 (the minimum of A + B): B leaves its domain (x ≥ 5).
	auto p = make_line_problem(0.0, 10.0);
	const Summary s = solve_with_accepted_first_step(p, 1, 0, 1);  // y had only B
	const auto& it = s.iterations_log[1];
	// A is linear, so over the factors evaluable at both points (A only) the model is exact: ρ = 1.
	// B's cost at x = 0 (2.0) is not credited as a decrease, and B's share of the model is left out.
	EXPECT_NEAR(it.cost_change, cost_a(0.0, 10.0) - it.cost, 1e-12);
	EXPECT_NEAR(it.relative_decrease, 1.0, 1e-12);
	// The evaluable set changed: the trust region is kept, not enlarged.
	EXPECT_EQ(it.trust_region_radius, s.iterations_log[0].trust_region_radius);
	// Then A alone is minimised exactly; B stays out and y is left without a factor.
	EXPECT_TRUE(s.is_solution_usable());
	EXPECT_NEAR(p.problem.value(p.x)[0], 10.0, 1e-6);  // LM stops at |Δcost| ≤ 1e-6·cost
	EXPECT_NEAR(s.final_cost, 0.0, 1e-12);
	EXPECT_EQ(s.num_dropped_factors, 1);
	EXPECT_EQ(s.num_unconstrained_variables, 1);
	EXPECT_EQ(p.problem.value(p.y)[0], 0.0);
	EXPECT_NE(format_iteration(it).find("(1 factor left their domain; 1 variable lost its last factor)"),
			  std::string::npos)
		<< format_iteration(it);
}

TEST(SolverDomain, FactorEnteringItsDomainIsNotChargedToTheStep)
{
	// From x = 8 (B out of its domain) A pulls x to ≈ 2: B enters with cost 0.5, which the step is
	// not charged; the logged cost is the full one, A + B.
	auto p = make_line_problem(8.0, 2.0);
	const Summary s = solve_with_accepted_first_step(p, 0, 1, 0);
	const auto& it = s.iterations_log[1];
	const double x1 = 8.0 - it.step_norm;  // y has no evaluable factor at x = 8 and does not move
	EXPECT_NEAR(it.cost, cost_a(x1, 2.0) + cost_b(x1), 1e-12);
	EXPECT_NEAR(it.cost_change, cost_a(8.0, 2.0) - cost_a(x1, 2.0), 1e-12);
	EXPECT_NEAR(it.relative_decrease, 1.0, 1e-12);
	EXPECT_EQ(it.trust_region_radius, s.iterations_log[0].trust_region_radius);
	// The minimum of A + B: (2 + 0.25·4) / 1.25.
	EXPECT_NEAR(p.problem.value(p.x)[0], 2.4, 1e-6);
	EXPECT_EQ(s.num_dropped_factors, 0);
	EXPECT_EQ(s.num_unconstrained_variables, 0);
}

TEST(SolverDomain, RejectedStepSaysWhy)
{
	Problem problem;
	const double x0 = 0.1;
	const VariableId x = problem.add_variable(&x0, euclidean_manifold(1));
	problem.add_factor(std::make_shared<SquareFactor>(), {x});
	const Summary s = solve(problem);
	ASSERT_GE(s.iterations_log.size(), 2u);
	const auto& it = s.iterations_log[1];  // x ≈ 20: the cost rises from 8 to ≈ 8e4
	EXPECT_FALSE(it.step_accepted);
	EXPECT_EQ(it.outcome, StepOutcome::CostRose);
	EXPECT_LT(it.cost_change, 0.0);
	const std::string row = format_iteration(it);
	EXPECT_EQ(row.substr(row.size() - 23), "  (rejected: cost rose)") << row;
	EXPECT_NEAR(problem.value(x)[0], 2.0, 1e-6);

	IterationSummary small;
	small.iteration = 3;
	small.outcome = StepOutcome::SmallGainRatio;
	small.factors_left = 2;
	small.factors_entered = 1;
	const std::string r2 = format_iteration(small);
	EXPECT_NE(r2.find("  (rejected: gain ratio below 1e-3; 2 factors left their domain, 1 entered)"), std::string::npos)
		<< r2;
	IterationSummary accepted;
	accepted.iteration = 4;
	accepted.step_accepted = true;
	EXPECT_EQ(format_iteration(accepted).find('('), std::string::npos);
}

TEST(SolverDomain, NoFactorEvaluableAtTheInitialValuesIsAFailureNotAFit)
{
	// B alone from x = 8: out of its domain there, so the cost is 0 over no factor and nothing has a
	// gradient; the solve fails at once and leaves x where it was.
	Problem problem;
	const double x0 = 8.0;
	const VariableId x = problem.add_variable(&x0, euclidean_manifold(1));
	problem.add_factor(std::make_shared<LineFactor>(0.5, 4.0, 5.0), {x});
	const Summary s = solve(problem);
	EXPECT_EQ(s.termination, TerminationType::Failure);
	EXPECT_EQ(s.message, "every factor dropped at the initial values: nothing to fit");
	EXPECT_FALSE(s.is_solution_usable());
	EXPECT_EQ(s.num_dropped_factors, 1);
	EXPECT_EQ(s.num_unconstrained_variables, 1);
	EXPECT_EQ(problem.value(x)[0], 8.0);
	// One evaluable factor is enough: from x = 4.5 the same factor is fitted.
	const double x1 = 4.5;
	Problem fits;
	const VariableId y = fits.add_variable(&x1, euclidean_manifold(1));
	fits.add_factor(std::make_shared<LineFactor>(0.5, 4.0, 5.0), {y});
	EXPECT_TRUE(solve(fits).is_solution_usable());
	EXPECT_NEAR(fits.value(y)[0], 4.0, 1e-6);
}
