// ReadingGate alone: the innovation distance against hand-computed values, the planar model's two rows,
// and the robust centre following the readings' consensus and not a gross reading.
#include <gtest/gtest.h>

#include "reading_gate.h"

#include <swba/core/chi2.h>
#include <swba/core/manifold.h>
#include <swba/factors/planar.h>

#include <cmath>
#include <vector>

using namespace swba;
using namespace swba::estimators;
using namespace swba::estimators::detail;

namespace
{
std::vector<double> gate_pose_value(double x, double y)
{
	std::vector<double> v(SE3Manifold::kAmbient);
	SE3Manifold::from_pose(mrpt::poses::CPose3D(x, y, 0, 0, 0, 0), v.data());
	return v;
}

/** A reading of world point `p` from a robot at (x, y) with heading 0 and the sensor at its origin. */
Observation gate_reading_of(const Eigen::Vector3d& p, double x, double y)
{
	const Eigen::Vector3d l = p - Eigen::Vector3d(x, y, 0);
	return {1, {l.norm(), std::atan2(l.y(), l.x()), -std::asin(l.z() / l.norm())}, {0.01, 0.001, 0.001}};
}
}  // namespace

TEST(ReadingGate, DistanceIsTheMahalanobisNormOfTheResidual)
{
	const ReadingGate gate(PoseModel::Spatial, chi2_quantile(0.99, 3));
	const auto x = gate_pose_value(0, 0);
	const Observation o{1, {5.1, 0, 0}, {0.1, 0.01, 0.01}};
	// r = (±0.1, 0, 0), S = R (1 + 1/n): with n = 1, d = 0.01 / (2 · 0.01).
	EXPECT_NEAR(gate.distance(Eigen::Vector3d(5, 0, 0), 1, o, {}, x.data(), nullptr), 0.5, 1e-12);
	EXPECT_NEAR(gate.distance(Eigen::Vector3d(5, 0, 0), 0, o, {}, x.data(), nullptr), 0.5, 1e-12);  // n = 0 counts as 1
	EXPECT_NEAR(gate.distance(Eigen::Vector3d(5, 0, 0), 3, o, {}, x.data(), nullptr), 0.75, 1e-12);
	// The pose's covariance widens the innovation covariance: the distance shrinks.
	const Eigen::MatrixXd pose_cov = 1e-2 * Eigen::MatrixXd::Identity(6, 6);
	const double d_pose = gate.distance(Eigen::Vector3d(5, 0, 0), 1, o, {}, x.data(), &pose_cov);
	EXPECT_LT(d_pose, 0.5);
	EXPECT_GT(d_pose, 0.0);
	const Observation exact{1, {5, 0, 0}, {0.1, 0.01, 0.01}};
	EXPECT_NEAR(gate.distance(Eigen::Vector3d(5, 0, 0), 1, exact, {}, x.data(), nullptr), 0.0, 1e-20);
}

TEST(ReadingGate, PlanarModelIgnoresThePitchRow)
{
	std::vector<double> x(SE3Manifold::kAmbient);
	SE3Manifold::from_pose(mrpt::poses::CPose3D(), x.data());
	const Observation pitched{1, {5, 0, 0.5}, {0.1, 0.01, 0.01}};
	const ReadingGate spatial(PoseModel::Spatial, 1.0), planar(PoseModel::Planar, 1.0);
	EXPECT_GT(spatial.distance(Eigen::Vector3d(5, 0, 0), 1, pitched, {}, x.data(), nullptr), 100.0);
	EXPECT_NEAR(planar.distance(Eigen::Vector3d(5, 0, 0), 1, pitched, {}, x.data(), nullptr), 0.0, 1e-20);
	EXPECT_EQ(planar.reading_sigma(pitched).size(), 2);
	// The planar pose's tangent is (ρx, ρy, ωz): a 3×3 pose covariance.
	const Eigen::MatrixXd pose_cov = 1e-2 * Eigen::MatrixXd::Identity(3, 3);
	EXPECT_NEAR(planar.distance(Eigen::Vector3d(5, 0, 0), 1, pitched, {}, x.data(), &pose_cov), 0.0, 1e-20);
}

TEST(ReadingGate, CentreFollowsTheReadingsConsensusNotAGrossReading)
{
	ReadingGate gate(PoseModel::Spatial, chi2_quantile(0.99, 3));
	EXPECT_EQ(gate.centre(), nullptr);
	gate.set_prediction_covariance(1e-2 * Eigen::MatrixXd::Identity(6, 6));  // σ = 0.1 per coordinate
	const auto predicted = gate_pose_value(0, 0);
	// The robot is at (0.2, 0): a 2σ odometry error the readings of three landmarks agree on; a fourth
	// reading is 2 m off.
	const std::vector<Eigen::Vector3d> points{{5, 0, 0}, {0, 5, 0}, {-5, 1, 0}, {3, -4, 0}};
	std::vector<Observation> obs;
	for (std::size_t i = 0; i < 3; i++) obs.push_back(gate_reading_of(points[i], 0.2, 0));
	obs.push_back(gate_reading_of(points[3] + Eigen::Vector3d(2, 0, 0), 0.2, 0));
	std::vector<GatedReading> readings;
	for (std::size_t i = 0; i < points.size(); i++) readings.push_back({points[i], 1000, &obs[i]});

	gate.centre_on(SE3Manifold(), predicted.data(), mrpt::poses::CPose3D(), {});
	ASSERT_NE(gate.centre(), nullptr);
	EXPECT_NEAR(SE3Manifold::to_pose(gate.centre()).x(), 0.0, 1e-12);  // no readings: the prediction

	gate.centre_on(SE3Manifold(), predicted.data(), mrpt::poses::CPose3D(), readings);
	const mrpt::poses::CPose3D c = SE3Manifold::to_pose(gate.centre());
	EXPECT_NEAR(c.x(), 0.2, 2e-3);
	EXPECT_NEAR(c.y(), 0.0, 2e-3);
	// At the centre the consistent readings are inside the gate and the gross one far outside.
	for (std::size_t i = 0; i < 3; i++)
		EXPECT_LT(gate.distance(points[i], 1000, obs[i], {}, gate.centre(), &gate.prediction_covariance()),
				  gate.threshold());
	EXPECT_GT(gate.distance(points[3], 1000, obs[3], {}, gate.centre(), &gate.prediction_covariance()),
			  5 * gate.threshold());
}

TEST(ReadingGate, ModelReadingFactorKeepsTheModelsRows)
{
	const Eigen::Vector3d sigma(0.1, 0.01, 0.02);
	const auto spatial = model_reading_factor(PoseModel::Spatial,
											  std::make_shared<RangeBearingXyzFactor>(RangeBearingMeasurement{5, 0, 0},
																					  mrpt::poses::CPose3D()),
											  sigma);
	EXPECT_EQ(spatial->residual_dim(), 3);
	EXPECT_EQ(spatial->tangent_dims(), (std::vector<int>{6, 3}));
	EXPECT_NEAR(spatial->sqrt_information()(2, 2), 50.0, 1e-9);
	const auto planar = model_reading_factor(PoseModel::Planar,
											 std::make_shared<RangeBearingXyzFactor>(RangeBearingMeasurement{5, 0, 0},
																					 mrpt::poses::CPose3D()),
											 sigma.head(2));
	EXPECT_EQ(planar->residual_dim(), 2);
	EXPECT_EQ(planar->tangent_dims(), (std::vector<int>{3, 2}));
}
