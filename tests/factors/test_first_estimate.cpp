// FirstEstimateFactor (swba/factors/first_estimate.h): the residual at the current values, the
// Jacobians at the registered first estimates.
#include "factor_test_fixtures.h"

#include <swba/factors/between_pose.h>
#include <swba/factors/first_estimate.h>

using namespace swba;
using namespace swba::factor_test;
using mrpt::poses::CPose3D;

namespace
{
using Block = Eigen::Matrix<double, 6, 6, Eigen::RowMajor>;
using Residual = Eigen::Matrix<double, 6, 1>;

/** The inner factor's residual and Jacobians at (a, b). */
void evaluate(const Factor& f, const Pose& a, const Pose& b, Residual* r, Block* Ja, Block* Jb)
{
	const double* x[] = {a.data(), b.data()};
	double* J[] = {Ja->data(), Jb->data()};
	ASSERT_TRUE(f.evaluate(x, r->data(), J));
}
}  // namespace

TEST(FirstEstimate, ResidualAtTheCurrentValuesJacobiansAtTheFirstEstimates)
{
	const auto inner = std::make_shared<BetweenPoseFactor>(CPose3D(1, 0.2, 0.1, 0.3, 0.05, -0.02));
	const Pose a = make_pose(CPose3D(0.1, 0.2, 0.3, 0.4, 0.1, 0.2));
	const Pose b = make_pose(CPose3D(1.2, 0.1, 0.5, 0.8, 0.0, 0.1));
	const Pose a_first = make_pose(CPose3D(0.0, 0.3, 0.2, 0.1, 0.0, 0.0));
	auto registry = std::make_shared<FirstEstimateRegistry>();
	const FirstEstimateFactor f(inner, {7, 8}, registry);

	Residual r, r_inner, r_first;
	Block Ja, Jb, Ja_inner, Jb_inner, Ja_first, Jb_first;
	evaluate(*inner, a, b, &r_inner, &Ja_inner, &Jb_inner);
	evaluate(f, a, b, &r, &Ja, &Jb);
	EXPECT_EQ(r, r_inner) << "no first estimate registered: the inner factor";
	EXPECT_EQ(Ja, Ja_inner);
	EXPECT_EQ(Jb, Jb_inner);

	(*registry)[7] = a_first;  // variable 7 (the first) frozen at a_first; b has none
	evaluate(f, a, b, &r, &Ja, &Jb);
	evaluate(*inner, a_first, b, &r_first, &Ja_first, &Jb_first);
	EXPECT_EQ(r, r_inner) << "the residual stays at the current values";
	EXPECT_EQ(Ja, Ja_first) << "Jacobians at (first estimate of a, current b)";
	EXPECT_EQ(Jb, Jb_first);
	EXPECT_GT((Ja_first - Ja_inner).norm(), 1e-3) << "the test needs the two linearisation points to differ";
}
