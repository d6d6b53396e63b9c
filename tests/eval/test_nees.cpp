// NEES: hand-computed values, the covariance-file reader, the frame of the ground truth, the χ² band.
#include <gtest/gtest.h>
#include <swba/eval/nees.h>

#include <cmath>
#include <sstream>

using namespace swba::eval;
using mrpt::poses::CPose3D;

namespace
{
constexpr double kPi = 3.14159265358979323846;

/** One covariance-file row: position diag (a, b, c), pose diag d[0..5], no correlations. */
std::string diagonal_row(double t, const std::vector<double>& p, const std::vector<double>& d)
{
	std::ostringstream s;
	s << t << " " << p[0] << " 0 0 " << p[1] << " 0 " << p[2];
	for (int i = 0; i < 6; i++)
		for (int j = i; j < 6; j++) s << " " << (i == j ? d[static_cast<std::size_t>(i)] : 0.0);
	return s.str() + "\n";
}
}  // namespace

TEST(Nees, DiagonalByHand)
{
	// e = (1, 2, 3), P = diag(1, 4, 9): 1 + 1 + 1.
	const NeesValue v = nees(Eigen::Vector3d(1, 2, 3), Eigen::Vector3d(1, 4, 9).asDiagonal().toDenseMatrix());
	EXPECT_DOUBLE_EQ(v.value, 3.0);
	EXPECT_EQ(v.dof, 3);
}

TEST(Nees, CorrelatedByHand)
{
	// P = [2 1; 1 2], P⁻¹ = [2 -1; -1 2] / 3, e = (1, 1): (2 - 1 - 1 + 2) / 3 = 2/3.
	Eigen::Matrix2d P;
	P << 2, 1, 1, 2;
	EXPECT_NEAR(nees(Eigen::Vector2d(1, 1), P).value, 2.0 / 3.0, 1e-15);
	// e = (1, -1): (2 + 1 + 1 + 2) / 3 = 2.
	EXPECT_NEAR(nees(Eigen::Vector2d(1, -1), P).value, 2.0, 1e-15);
}

TEST(Nees, ZeroRowAndColumnIsAFixedDofLeftOut)
{
	// P = diag(4, 0, 1): the middle dof is fixed; its error (5) does not count. (2²/4) + 1 = 2 with 2 dof.
	const NeesValue v = nees(Eigen::Vector3d(2, 5, 1), Eigen::Vector3d(4, 0, 1).asDiagonal().toDenseMatrix());
	EXPECT_DOUBLE_EQ(v.value, 2.0);
	EXPECT_EQ(v.dof, 2);
}

TEST(Nees, InvalidCovariancesAreErrors)
{
	Eigen::Matrix2d zero_diag_not_zero_row;
	zero_diag_not_zero_row << 0, 1, 1, 2;
	EXPECT_THROW(nees(Eigen::Vector2d(1, 1), zero_diag_not_zero_row), std::invalid_argument);
	Eigen::Matrix2d indefinite;
	indefinite << 1, 2, 2, 1;
	EXPECT_THROW(nees(Eigen::Vector2d(1, 1), indefinite), std::invalid_argument);
	EXPECT_THROW(nees(Eigen::Vector2d(1, 1), Eigen::Matrix2d::Zero()), std::invalid_argument);
	EXPECT_THROW(nees(Eigen::Vector3d(1, 1, 1), Eigen::Matrix2d::Identity()), std::invalid_argument);
}

TEST(Nees, PositionErrorIsInTheWorldFrame)
{
	// Estimate at (1, 2, 3) turned 90° in yaw, truth at (2, 2, 3): e = (1, 0, 0) in the world frame,
	// whatever the estimate's rotation; σ_x = 0.5 → 1 / 0.25 = 4.
	const CPose3D est(1, 2, 3, kPi / 2, 0, 0), truth(2, 2, 3, 0, 0, 0);
	const NeesValue v = position_nees(est, truth, Eigen::Vector3d(0.25, 1, 1).asDiagonal().toDenseMatrix());
	EXPECT_NEAR(v.value, 4.0, 1e-12);
	EXPECT_EQ(v.dof, 3);
}

TEST(Nees, PoseErrorIsTheRightPerturbation)
{
	// Estimate at the origin turned 90° in yaw; truth 1 m along world y and 0.1 rad more yaw:
	// ρ = R_estᵀ (0, 1, 0) = (1, 0, 0) (the estimate's own x axis), ω = (0, 0, 0.1).
	const CPose3D est(0, 0, 0, kPi / 2, 0, 0), truth(0, 1, 0, kPi / 2 + 0.1, 0, 0);
	const auto d = pose_error_tangent(est, truth);
	EXPECT_NEAR(d(0), 1.0, 1e-12);
	EXPECT_NEAR(d(1), 0.0, 1e-12);
	EXPECT_NEAR(d(5), 0.1, 1e-12);
	EXPECT_NEAR(d.segment<3>(2).norm(), 0.0, 1e-12);
	// T_est · Exp(δ) = T_true (translation part: t_est + R_est ρ).
	const CPose3D back = est + CPose3D(d(0), d(1), d(2), d(5), d(4), d(3));
	EXPECT_NEAR(back.y(), 1.0, 1e-12);
	// σ_ρx² = 0.5, σ_ωz² = 0.01: 1/0.5 + 0.01/0.01 = 3.
	Eigen::Matrix<double, 6, 1> diag;
	diag << 0.5, 1, 1, 1, 1, 0.01;
	const NeesValue v = pose_nees(est, truth, diag.asDiagonal().toDenseMatrix());
	EXPECT_NEAR(v.value, 3.0, 1e-10);
	EXPECT_EQ(v.dof, 6);
}

TEST(CovarianceFile, UpperTrianglesFillSymmetricMatrices)
{
	std::ostringstream row;
	row << "# stamp, position, pose\n\n2";
	for (int k = 1; k <= 27; k++) row << " " << k;
	std::istringstream in(row.str() + "\n");
	const auto rows = read_covariance_file(in, "test.cov");
	ASSERT_EQ(rows.size(), 1u);
	EXPECT_EQ(rows[0].stamp, 2.0);
	// position: xx xy xz yy yz zz = 1 .. 6
	EXPECT_EQ(rows[0].position(0, 0), 1);
	EXPECT_EQ(rows[0].position(1, 0), 2);
	EXPECT_EQ(rows[0].position(0, 2), 3);
	EXPECT_EQ(rows[0].position(2, 0), 3);
	EXPECT_EQ(rows[0].position(1, 1), 4);
	EXPECT_EQ(rows[0].position(2, 1), 5);
	EXPECT_EQ(rows[0].position(2, 2), 6);
	// pose: row 0 = 7..12, row 1 = 13..17, row 2 = 18..21, row 3 = 22..24, row 4 = 25, 26, row 5 = 27
	EXPECT_EQ(rows[0].pose(0, 0), 7);
	EXPECT_EQ(rows[0].pose(5, 0), 12);
	EXPECT_EQ(rows[0].pose(1, 1), 13);
	EXPECT_EQ(rows[0].pose(2, 2), 18);
	EXPECT_EQ(rows[0].pose(3, 3), 22);
	EXPECT_EQ(rows[0].pose(5, 3), 24);
	EXPECT_EQ(rows[0].pose(4, 4), 25);
	EXPECT_EQ(rows[0].pose(4, 5), 26);
	EXPECT_EQ(rows[0].pose(5, 5), 27);
	// Written and read back: the same numbers.
	std::ostringstream out;
	write_covariance_file(out, rows);
	std::istringstream again(out.str());
	const auto back = read_covariance_file(again, "again.cov");
	EXPECT_EQ(back[0].pose, rows[0].pose);
	EXPECT_EQ(back[0].position, rows[0].position);
}

TEST(CovarianceFile, ErrorsNameFileAndLine)
{
	auto message = [](const std::string& text) {
		std::istringstream in(text);
		try
		{
			read_covariance_file(in, "x.cov");
		}
		catch (const TrajectoryFileError& e)
		{
			return std::string(e.what());
		}
		return std::string("no error");
	};
	const std::string good = diagonal_row(1, {1, 1, 1}, {1, 1, 1, 1, 1, 1});
	EXPECT_EQ(message(good + "2 1 2 3\n"), "x.cov:2: 4 numbers, expected 28 (stamp, 6 position covariance entries "
										   "xx xy xz yy yz zz, 21 pose covariance entries)");
	std::string bad = diagonal_row(2, {1, 1, 1}, {1, 1, 1, 1, 1, 1});
	bad.replace(bad.find(' '), 1, " abc ");
	EXPECT_EQ(message("# c\n" + good + bad), "x.cov:3: column 2: 'abc' is not a number");
	EXPECT_EQ(message(diagonal_row(2, {1, 1, 1}, {1, 1, 1, 1, 1, 1}) + good), "x.cov:2: stamp decreases");
	EXPECT_EQ(message(diagonal_row(1, {1, -1, 1}, {1, 1, 1, 1, 1, 1})), "x.cov:1: negative position variance");
	EXPECT_EQ(message(diagonal_row(1, {1, 1, 1}, {1, 1, 1, 1, 1, std::nan("")})), "x.cov:1: column 28 is not finite");
	EXPECT_THROW(read_covariance_file("/nonexistent/x.cov"), TrajectoryFileError);
}

TEST(RunNees, GroundTruthIsTakenRelativeToItsFirstRow)
{
	// The ground truth starts at A, not at the origin; the estimate (first pose = origin) is exactly
	// A⁻¹·T_k: every NEES is 0. Without the change of frame the error would be A's offset.
	const CPose3D A(5, -2, 1, 0.3, 0.1, -0.2), B(1, 1, 0, 0.2, 0, 0), C(2, 1, 0.5, 0.4, 0.05, 0);
	const std::vector<CPose3D> gt = {A, A + B, A + C};
	Trajectory est;
	est.push_back(1, B);
	est.push_back(2, C);
	std::istringstream cov(diagonal_row(1, {1, 1, 1}, {1, 1, 1, 1, 1, 1}) + diagonal_row(2, {1, 1, 1}, {1, 1, 1, 1, 1, 1}));
	const RunNees r = run_nees(est, read_covariance_file(cov, "c.cov"), gt, "c.cov");
	ASSERT_EQ(r.stamps.size(), 2u);
	EXPECT_NEAR(r.position[1].value, 0.0, 1e-20);
	EXPECT_NEAR(r.pose[1].value, 0.0, 1e-20);
	// One metre off along world x at t = 2 with σ² = 0.5: position NEES 2.
	est.poses[1] = CPose3D(C.x() - 1, C.y(), C.z(), C.yaw(), C.pitch(), C.roll());
	std::istringstream cov2(diagonal_row(1, {1, 1, 1}, {1, 1, 1, 1, 1, 1}) +
							diagonal_row(2, {0.5, 1, 1}, {1, 1, 1, 1, 1, 1}));
	const RunNees r2 = run_nees(est, read_covariance_file(cov2, "c.cov"), gt, "c.cov");
	EXPECT_NEAR(r2.position[1].value, 2.0, 1e-9);
}

TEST(RunNees, APoseWithZeroCovarianceIsLeftOutAndCounted)
{
	// An EKF before its first prediction: the pose at t = 1 has no uncertainty at all. It has no NEES; the
	// pose at t = 2 does. Only one of the two covariances zero is an error.
	const std::vector<CPose3D> gt = {CPose3D(), CPose3D(), CPose3D(1, 0, 0, 0, 0, 0)};
	Trajectory est;
	est.push_back(1, CPose3D());
	est.push_back(2, CPose3D());
	std::istringstream cov(diagonal_row(1, {0, 0, 0}, {0, 0, 0, 0, 0, 0}) + diagonal_row(2, {0.25, 1, 1}, {1, 1, 1, 1, 1, 1}));
	const RunNees r = run_nees(est, read_covariance_file(cov, "c.cov"), gt, "c.cov");
	EXPECT_EQ(r.fixed_poses, 1u);
	ASSERT_EQ(r.stamps, (std::vector<double>{2}));
	EXPECT_DOUBLE_EQ(r.position[0].value, 4.0);
	std::istringstream half(diagonal_row(1, {0, 0, 0}, {1, 1, 1, 1, 1, 1}) + diagonal_row(2, {1, 1, 1}, {1, 1, 1, 1, 1, 1}));
	try
	{
		run_nees(est, read_covariance_file(half, "c.cov"), gt, "c.cov");
		ADD_FAILURE() << "no error";
	}
	catch (const std::runtime_error& e)
	{
		EXPECT_STREQ(e.what(), "c.cov: row 1: the position covariance is zero but the pose one is not");
	}
}

TEST(RunNees, MismatchesAreErrorsNamingTheFileAndRow)
{
	const std::vector<CPose3D> gt = {CPose3D(), CPose3D(), CPose3D()};
	Trajectory est;
	est.push_back(1, CPose3D());
	est.push_back(2, CPose3D());
	std::istringstream one(diagonal_row(1, {1, 1, 1}, {1, 1, 1, 1, 1, 1}));
	EXPECT_THROW(
		{
			try
			{
				run_nees(est, read_covariance_file(one, "c.cov"), gt, "c.cov");
			}
			catch (const std::runtime_error& e)
			{
				EXPECT_STREQ(e.what(), "c.cov: 1 rows, but the trajectory has 2 poses (one row per pose expected)");
				throw;
			}
		},
		std::runtime_error);
	std::istringstream shifted(diagonal_row(1, {1, 1, 1}, {1, 1, 1, 1, 1, 1}) + diagonal_row(3, {1, 1, 1}, {1, 1, 1, 1, 1, 1}));
	EXPECT_THROW(run_nees(est, read_covariance_file(shifted, "c.cov"), gt, "c.cov"), std::runtime_error);
	std::istringstream indefinite(diagonal_row(1, {1, 1, 1}, {1, 1, 1, 1, 1, 1}) +
								  "2 1 2 0 1 0 1 1 0 0 0 0 0 1 0 0 0 0 1 0 0 0 1 0 0 1 0 1\n");
	try
	{
		run_nees(est, read_covariance_file(indefinite, "c.cov"), gt, "c.cov");
		ADD_FAILURE() << "no error";
	}
	catch (const std::runtime_error& e)
	{
		EXPECT_STREQ(e.what(), "c.cov: row 2: covariance is not positive definite");
	}
}

TEST(NeesBand, WilsonHilfertyReferences)
{
	// N = 50 runs: 3 dof → [2.36, 3.72]; 6 dof → [5.08, 7.00] (two decimals).
	const NeesBand b3 = nees_band(50, 150);
	EXPECT_NEAR(b3.low, 2.36, 0.005);
	EXPECT_NEAR(b3.high, 3.72, 0.005);
	const NeesBand b6 = nees_band(50, 300);
	EXPECT_NEAR(b6.low, 5.08, 0.005);
	EXPECT_NEAR(b6.high, 7.00, 0.005);
	// One run, 1 dof: the χ²₁ quantiles 0.000982 and 5.024.
	const NeesBand b1 = nees_band(1, 1);
	EXPECT_NEAR(b1.low, 0.000982, 1e-6);
	EXPECT_NEAR(b1.high, 5.0239, 1e-4);
	EXPECT_THROW(nees_band(0, 3), std::invalid_argument);
	EXPECT_THROW(nees_band(2, 3, 1.0), std::invalid_argument);
}

TEST(AverageNees, MeanPerStepOverTheRunsThatHaveIt)
{
	RunNees a, b;
	a.stamps = {1, 2};
	a.position = {{1.0, 3}, {4.0, 3}};
	a.pose = {{6.0, 6}, {2.0, 6}};
	b.stamps = {1};
	b.position = {{3.0, 3}};
	b.pose = {{8.0, 6}};
	const AverageNees avg = average_nees({a, b});
	ASSERT_EQ(avg.stamps, (std::vector<double>{1, 2}));
	EXPECT_EQ(avg.runs, (std::vector<std::size_t>{2, 1}));
	EXPECT_EQ(avg.position.mean, (std::vector<double>{2.0, 4.0}));
	EXPECT_EQ(avg.position.dof_sum, (std::vector<int>{6, 3}));
	EXPECT_EQ(avg.pose.mean, (std::vector<double>{7.0, 2.0}));
	// Step 1: 2 runs, 6 dof, band [χ²₆(0.025)/2, χ²₆(0.975)/2] = [1.2373/2, 14.449/2]: 2 inside. Step 2: 1 run,
	// 3 dof, [0.2158, 9.3484]: 4 inside. Pose step 2: [0.8312, 14.449]: 2 inside.
	EXPECT_NEAR(avg.position.band[0].low, 0.61867, 1e-4);
	EXPECT_NEAR(avg.position.band[0].high, 7.2247, 1e-3);
	EXPECT_NEAR(avg.position.band[1].low, 0.2158, 1e-4);
	EXPECT_NEAR(avg.position.band[1].high, 9.3484, 1e-3);
	EXPECT_DOUBLE_EQ(avg.position.share_in_band, 1.0);
	EXPECT_DOUBLE_EQ(avg.position.mean_over_steps, 3.0);
	EXPECT_DOUBLE_EQ(avg.pose.mean_over_steps, 4.5);
	// A mean outside its band counts as outside: 40 at step 2.
	a.position[1].value = 40;
	EXPECT_DOUBLE_EQ(average_nees({a, b}).position.share_in_band, 0.5);
}
