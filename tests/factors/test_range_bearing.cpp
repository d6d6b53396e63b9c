// Tests of the range-bearing factors (XYZ and inverse-depth landmarks), the sensor model against
// MRPT's, the wrapped angle residuals, and the inverse-depth conversions.
#include "factor_test_fixtures.h"

#include <swba/factors/range_bearing.h>



using namespace swba;
using namespace swba::factor_test;
using mrpt::poses::CPose3D;

namespace
{
/** The kf-slam_6D_demo_noncentered sensor mounting: (0.5, 0.2, 0.1) m, yaw 80°, pitch −20°, roll 10°. */
CPose3D noncentered_sensor() { return CPose3D(0.5, 0.2, 0.1, mrpt::DEG2RAD(80.0), mrpt::DEG2RAD(-20.0), mrpt::DEG2RAD(10.0)); }

/** World point seen at `l` (sensor frame) by a sensor at S = T ⊕ sensor. */
Eigen::Vector3d world_of(const Pose& T, const CPose3D& sensor, const Eigen::Vector3d& l)
{
	const Eigen::Matrix3d Rs = sensor.getRotationMatrix().asEigen();
	const Eigen::Vector3d ts(sensor.x(), sensor.y(), sensor.z());
	return rotation(T) * (Rs * l + ts) + translation(T);
}

Eigen::Vector3d model(const Eigen::Vector3d& l)
{
	Eigen::Vector3d h;
	EXPECT_TRUE(range_bearing_model(l, h));
	return h;
}

RangeBearingMeasurement measurement_of(const Eigen::Vector3d& h) { return {h[0], h[1], h[2]}; }

Eigen::Vector3d eval3(const Factor& f, const std::vector<const double*>& x)
{
	Eigen::Vector3d r;
	EXPECT_TRUE(f.evaluate(x.data(), r.data(), nullptr));
	return r;
}

/** A robot pose, a sensor mounting and a landmark in the sensor frame. */
struct RbCase
{
	std::string name;
	Pose T;
	CPose3D sensor;
	Eigen::Vector3d l;	// landmark in the sensor frame
};

std::vector<RbCase> rb_cases()
{
	Rng rng(42);
	std::vector<RbCase> c;
	for (int k = 0; k < 6; k++)
		c.push_back({"random " + std::to_string(k), rng.pose(), k % 2 ? noncentered_sensor() : CPose3D(),
					 rng.unit() * rng.uniform(0.5, 10.0)});
	c.push_back({"small angles", make_pose(axis_angle(1e-5, rng.unit()), rng.vec(-1, 1)),
				 CPose3D(0.1, 0, 0, 1e-5, -1e-5, 1e-5), Eigen::Vector3d(4.0, 1e-5, -1e-5)});
	c.push_back({"robot rotated by pi", make_pose(axis_angle(M_PI, rng.unit()), rng.vec(-5, 5)), noncentered_sensor(),
				 Eigen::Vector3d(2.0, -3.0, 1.0)});
	c.push_back({"robot rotated by pi-1e-9", make_pose(axis_angle(M_PI - 1e-9, rng.unit()), rng.vec(-5, 5)),
				 noncentered_sensor(), Eigen::Vector3d(-1.0, 2.0, 0.5)});
	// Behind the sensor, on the atan2 branch cut: yaw = ±π flips under perturbation; wrapping keeps r smooth.
	c.push_back({"yaw at the branch cut", rng.pose(), noncentered_sensor(), Eigen::Vector3d(-5.0, 1e-12, 0.3)});
	c.push_back({"steep pitch (~89 deg)", rng.pose(), noncentered_sensor(), Eigen::Vector3d(0.05, 0.02, -5.0)});
	c.push_back({"far (100 m)", rng.pose(), noncentered_sensor(), 100.0 * rng.unit()});
	c.push_back({"near (5 cm)", rng.pose(), noncentered_sensor(), 0.05 * rng.unit()});
	return c;
}

/** Noise added to the exact measurement so that residuals are not zero. */
RangeBearingMeasurement noisy(const Eigen::Vector3d& h, Rng& rng)
{
	return {h[0] + 0.01 * rng.normal(), wrap_to_pi(h[1] + 0.002 * rng.normal()), h[2] + 0.002 * rng.normal()};
}
}  // namespace

// ------------------------------------------------------------------------------------------------
TEST(RangeBearing, ResidualWrapsYawAndPitchAcrossPlusMinusPi)
{
	// Landmark just behind the sensor (yaw = π − 1e-3) measured at yaw = −π + 1e-3: residual −2e-3, not 2π − 2e-3.
	const Pose T = make_pose(Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero());
	const Eigen::Vector3d p(-5.0 * std::cos(1e-3), 5.0 * std::sin(1e-3), 0.0);
	RangeBearingXyzFactor f({5.0, -M_PI + 1e-3, 0.0}, CPose3D());
	const Eigen::Vector3d r = eval3(f, {T.data(), p.data()});
	EXPECT_NEAR(r[0], 0.0, 1e-12);
	EXPECT_NEAR(r[1], -2e-3, 1e-12);
	EXPECT_NEAR(r[2], 0.0, 1e-12);
	RangeBearingXyzFactor g({5.0, M_PI - 1e-3, 2 * M_PI}, CPose3D());	 // pitch measured as 2π ≡ 0
	const Eigen::Vector3d q(-5.0 * std::cos(1e-3), -5.0 * std::sin(1e-3), 0.0);  // yaw −π + 1e-3
	const Eigen::Vector3d s = eval3(g, {T.data(), q.data()});
	EXPECT_NEAR(s[1], 2e-3, 1e-12);
	EXPECT_NEAR(s[2], 0.0, 1e-12);
}

TEST(RangeBearing, ModelAgreesWithMrptSphericalCoordinates)
{
	// MRPT's simulator (CLandmarksMap::simulateRangeBearingReadings) and EKF use
	// (robot ⊕ sensor).sphericalCoordinates(landmark); our factor must predict exactly that.
	Rng rng(99);
	for (const CPose3D& sensor : {noncentered_sensor(), CPose3D()})
		for (int k = 0; k < 20; k++)
		{
			const CPose3D robot(rng.uniform(-5, 5), rng.uniform(-5, 5), rng.uniform(-1, 1), rng.uniform(-M_PI, M_PI),
								rng.uniform(-1.5, 1.5), rng.uniform(-M_PI, M_PI));
			const Eigen::Vector3d p = rng.vec(-10, 10);
			double range, yaw, pitch;
			(robot + sensor).sphericalCoordinates(mrpt::math::TPoint3D(p.x(), p.y(), p.z()), range, yaw, pitch);
			const Pose T = make_pose(robot);
			RangeBearingXyzFactor f({range, yaw, pitch}, sensor);
			const Eigen::Vector3d r = eval3(f, {T.data(), p.data()});
			EXPECT_LE(r.cwiseAbs().maxCoeff(), 1e-12 * std::max(1.0, range)) << "k = " << k;
			// REFERENCE.md's formula through MRPT's own inverse composition.
			const auto l = (robot + sensor).inverseComposePoint(mrpt::math::TPoint3D(p.x(), p.y(), p.z()));
			const double n = std::sqrt(l.x * l.x + l.y * l.y + l.z * l.z);
			const Eigen::Vector3d h = model(Eigen::Vector3d(l.x, l.y, l.z));
			EXPECT_NEAR(h[0], n, 1e-12 * n);
			EXPECT_NEAR(h[1], std::atan2(l.y, l.x), 1e-12);
			EXPECT_NEAR(h[2], -std::asin(l.z / n), 1e-12);
		}
}

TEST(RangeBearing, ModelIsUndefinedOnTheSensorAxis)
{
	Eigen::Vector3d h;
	EXPECT_FALSE(range_bearing_model(Eigen::Vector3d::Zero(), h));
	EXPECT_FALSE(range_bearing_model(Eigen::Vector3d(0, 0, 3), h));
	EXPECT_FALSE(range_bearing_model(Eigen::Vector3d(NAN, 1, 1), h));
	EXPECT_TRUE(range_bearing_model(Eigen::Vector3d(1e-9, 0, 3), h));
}

TEST(RangeBearing, FactorsRejectBadMeasurements)
{
	EXPECT_THROW(RangeBearingXyzFactor({0.0, 0.1, 0.1}, CPose3D()), std::invalid_argument);
	EXPECT_THROW(RangeBearingXyzFactor({-1.0, 0.1, 0.1}, CPose3D()), std::invalid_argument);
	EXPECT_THROW(RangeBearingXyzFactor({NAN, 0.1, 0.1}, CPose3D()), std::invalid_argument);
	EXPECT_THROW(RangeBearingInverseDepthFactor({1.0, INFINITY, 0.1}, CPose3D()), std::invalid_argument);
	EXPECT_THROW(RangeBearingInverseDepthAnchorFactor({1.0, 0.1, NAN}), std::invalid_argument);
}

// ------------------------------------------------------------------------------------------------
TEST(RangeBearingXyz, ZeroResidualAtTruth)
{
	for (const auto& c : rb_cases())
	{
		const Eigen::Vector3d p = world_of(c.T, c.sensor, c.l);
		RangeBearingXyzFactor f(measurement_of(model(c.l)), c.sensor);
		EXPECT_LE(eval3(f, {c.T.data(), p.data()}).cwiseAbs().maxCoeff(), 1e-10) << c.name;
	}
}

TEST(RangeBearingXyz, JacobiansMatchNumeric)
{
	Rng rng(1);
	const auto cases = rb_cases();
	ASSERT_GE(cases.size(), 5u);
	for (const auto& c : cases)
	{
		const Eigen::Vector3d p = world_of(c.T, c.sensor, c.l);
		RangeBearingXyzFactor f(noisy(model(c.l), rng), c.sensor);
		expect_jacobians_match(f, {c.T.data(), p.data()}, {se3(), rn(3)}, "RangeBearingXyzFactor", c.name);
	}
}

TEST(RangeBearingXyz, UndefinedAtTheSensorOrigin)
{
	const Pose T = make_pose(Eigen::Matrix3d::Identity(), Eigen::Vector3d(1, 2, 3));
	const CPose3D sensor(0.5, 0.25, -1.0, 0, 0, 0);	// exact arithmetic: l is exactly 0 / on the axis
	RangeBearingXyzFactor f({1.0, 0.0, 0.0}, sensor);
	Eigen::Vector3d r;
	for (const Eigen::Vector3d& p : {Eigen::Vector3d(1.5, 2.25, 2.0), Eigen::Vector3d(1.5, 2.25, 7.0)})
	{
		const double* x[2] = {T.data(), p.data()};
		EXPECT_FALSE(f.evaluate(x, r.data(), nullptr)) << p.transpose();
	}
}

// ------------------------------------------------------------------------------------------------
namespace
{
/** An anchor pose, an observing pose and a landmark, with (possibly different) sensors. */
struct IdCase
{
	std::string name;
	Pose Ta, To;
	CPose3D sensor_a, sensor_o;
	Eigen::Vector3d p;	// world point
};

std::vector<IdCase> id_cases()
{
	Rng rng(77);
	std::vector<IdCase> c;
	const CPose3D nc = noncentered_sensor();
	for (int k = 0; k < 6; k++)
	{
		const Pose Ta = rng.pose();
		const Pose To = rng.pose();
		c.push_back({"random " + std::to_string(k), Ta, To, k % 2 ? nc : CPose3D(), k % 2 ? nc : CPose3D(),
					 world_of(Ta, k % 2 ? nc : CPose3D(), rng.unit() * rng.uniform(1, 10))});
	}
	{
		const Pose Ta = make_pose(axis_angle(1e-5, rng.unit()), rng.vec(-0.1, 0.1));
		const Pose To = make_pose(axis_angle(-2e-5, rng.unit()), Ta.empty() ? Eigen::Vector3d::Zero() : rng.vec(-0.1, 0.1));
		c.push_back({"small angles, small baseline", Ta, To, CPose3D(), CPose3D(), world_of(Ta, CPose3D(), {5.0, 1e-5, -1e-5})});
	}
	{
		const Pose Ta = make_pose(axis_angle(M_PI, rng.unit()), rng.vec(-3, 3));
		const Pose To = make_pose(axis_angle(M_PI - 1e-9, rng.unit()), rng.vec(-3, 3));
		c.push_back({"poses at pi", Ta, To, nc, nc, world_of(Ta, nc, {2.0, 1.0, -0.5})});
	}
	{
		const Pose Ta = rng.pose(), To = rng.pose();
		c.push_back({"different sensors", Ta, To, nc, CPose3D(-0.3, 0.1, 0.2, 2.0, 0.3, -0.4), world_of(Ta, nc, {3.0, -2.0, 1.0})});
	}
	{
		const Pose Ta = rng.pose(), To = rng.pose();
		c.push_back({"far (200 m, rho = 5e-3)", Ta, To, nc, nc, world_of(Ta, nc, 200.0 * rng.unit())});
	}
	{
		const Pose Ta = rng.pose(), To = rng.pose();
		// Seen at the anchor with elevation ≈ 89° (θ ill-conditioned) — the direction is still well defined.
		c.push_back({"steep anchor bearing", Ta, To, nc, nc, world_of(Ta, nc, {0.03, 0.05, -4.0})});
	}
	return c;
}
}  // namespace

TEST(RangeBearingInverseDepth, ZeroResidualAtTruthAndEqualsXyzFactor)
{
	Rng rng(4);
	for (const auto& c : id_cases())
	{
		const Eigen::Vector3d lambda = world_to_inverse_depth(c.Ta.data(), c.sensor_a, c.p);
		// The observing sensor sees l = S_o⁻¹ ⊕ p.
		const Eigen::Matrix3d Rso = c.sensor_o.getRotationMatrix().asEigen();
		const Eigen::Vector3d tso(c.sensor_o.x(), c.sensor_o.y(), c.sensor_o.z());
		const Eigen::Vector3d l = Rso.transpose() * (rotation(c.To).transpose() * (c.p - translation(c.To)) - tso);
		RangeBearingInverseDepthFactor exact(measurement_of(model(l)), c.sensor_o, c.sensor_a);
		EXPECT_LE(eval3(exact, {c.Ta.data(), c.To.data(), lambda.data()}).cwiseAbs().maxCoeff(), 1e-9) << c.name;
		// With noise: the same residual as the XYZ factor at p_world(λ).
		const RangeBearingMeasurement z = noisy(model(l), rng);
		RangeBearingInverseDepthFactor f(z, c.sensor_o, c.sensor_a);
		RangeBearingXyzFactor g(z, c.sensor_o);
		const Eigen::Vector3d p = inverse_depth_to_world(c.Ta.data(), c.sensor_a, lambda);
		EXPECT_LE((eval3(f, {c.Ta.data(), c.To.data(), lambda.data()}) - eval3(g, {c.To.data(), p.data()}))
					  .cwiseAbs()
					  .maxCoeff(),
				  1e-9)
			<< c.name;
	}
}

TEST(RangeBearingInverseDepth, JacobiansMatchNumeric)
{
	Rng rng(8);
	const auto cases = id_cases();
	ASSERT_GE(cases.size(), 5u);
	for (const auto& c : cases)
	{
		const Eigen::Vector3d lambda = world_to_inverse_depth(c.Ta.data(), c.sensor_a, c.p);
		const Eigen::Matrix3d Rso = c.sensor_o.getRotationMatrix().asEigen();
		const Eigen::Vector3d tso(c.sensor_o.x(), c.sensor_o.y(), c.sensor_o.z());
		const Eigen::Vector3d l = Rso.transpose() * (rotation(c.To).transpose() * (c.p - translation(c.To)) - tso);
		RangeBearingInverseDepthFactor f(noisy(model(l), rng), c.sensor_o, c.sensor_a);
		expect_jacobians_match(f, {c.Ta.data(), c.To.data(), lambda.data()}, {se3(), se3(), rn(3)},
							   "RangeBearingInverseDepthFactor", c.name);
	}
}

TEST(RangeBearingInverseDepth, UndefinedForNonPositiveOrNonFiniteInverseRange)
{
	Rng rng(12);
	const Pose Ta = rng.pose(), To = rng.pose();
	RangeBearingInverseDepthFactor f({3.0, 0.2, 0.1}, noncentered_sensor());
	RangeBearingInverseDepthAnchorFactor g({3.0, 0.2, 0.1});
	for (const Eigen::Vector3d& lambda :
		 {Eigen::Vector3d(0.1, 0.2, 0.0), Eigen::Vector3d(0.1, 0.2, -0.5), Eigen::Vector3d(NAN, 0.2, 0.5),
		  Eigen::Vector3d(0.1, 0.2, INFINITY)})
	{
		Eigen::Vector3d r;
		const double* x[3] = {Ta.data(), To.data(), lambda.data()};
		EXPECT_FALSE(f.evaluate(x, r.data(), nullptr)) << lambda.transpose();
		const double* y[1] = {lambda.data()};
		EXPECT_FALSE(g.evaluate(y, r.data(), nullptr)) << lambda.transpose();
	}
}

TEST(RangeBearingInverseDepthAnchor, FirstObservationInitialisesLambdaExactly)
{
	Rng rng(21);
	for (int k = 0; k < 10; k++)
	{
		const Eigen::Vector3d l = rng.unit() * rng.uniform(0.5, 10);
		const RangeBearingMeasurement z = measurement_of(model(l));
		const Eigen::Vector3d lambda = inverse_depth_from_measurement(z);
		EXPECT_EQ(lambda[0], z.yaw);
		EXPECT_EQ(lambda[1], z.pitch);
		EXPECT_EQ(lambda[2], 1.0 / z.range);
		RangeBearingInverseDepthAnchorFactor f(z);
		EXPECT_LE(eval3(f, {lambda.data()}).cwiseAbs().maxCoeff(), 1e-12);
		EXPECT_LE((inverse_depth_to_sensor_point(lambda) - l).norm(), 1e-12 * l.norm());
	}
}

TEST(RangeBearingInverseDepthAnchor, JacobiansMatchNumeric)
{
	Rng rng(31);
	struct C
	{
		std::string name;
		Eigen::Vector3d lambda;
	};
	std::vector<C> cases;
	for (int k = 0; k < 5; k++)
		cases.push_back({"random " + std::to_string(k),
						 Eigen::Vector3d(rng.uniform(-M_PI, M_PI), rng.uniform(-1.4, 1.4), rng.uniform(0.1, 2))});
	cases.push_back({"theta near pi (wrap)", Eigen::Vector3d(M_PI - 1e-9, 0.2, 0.5)});
	cases.push_back({"theta near -pi (wrap)", Eigen::Vector3d(-M_PI + 1e-9, -0.3, 0.5)});
	cases.push_back({"small angles", Eigen::Vector3d(1e-5, -1e-5, 0.3)});
	cases.push_back({"steep (phi = 1.55)", Eigen::Vector3d(0.4, 1.55, 0.3)});
	cases.push_back({"far (rho = 1e-2)", Eigen::Vector3d(0.4, 0.1, 1e-2)});
	cases.push_back({"very far (rho = 1e-3)", Eigen::Vector3d(0.4, 0.1, 1e-3)});
	cases.push_back({"near (rho = 20)", Eigen::Vector3d(-2.0, 0.1, 20.0)});
	for (const auto& c : cases)
	{
		const RangeBearingMeasurement z = noisy(model(inverse_depth_to_sensor_point(c.lambda)), rng);
		RangeBearingInverseDepthAnchorFactor f(z);
		// The central difference's truncation error on ∂range/∂ρ = −1/ρ² is h²/ρ⁴: with the default
		// h = 1e-6 it reaches the 1e-6 bound at ρ = 1e-3 (a fault of the reference, not of the factor),
		// so the step is scaled down there (rounding error ε·range/h stays ~1e-11 relative).
		const double h = c.lambda[2] < 5e-3 ? 1e-8 : 1e-6;
		expect_jacobians_match(f, {c.lambda.data()}, {rn(3)}, "RangeBearingInverseDepthAnchorFactor", c.name, h);
	}
}

// ------------------------------------------------------------------------------------------------
TEST(InverseDepthConversion, WorldRoundTrips)
{
	Rng rng(55);
	for (const auto& c : id_cases())
	{
		// world → λ → world
		const Eigen::Vector3d lambda = world_to_inverse_depth(c.Ta.data(), c.sensor_a, c.p);
		const Eigen::Vector3d p = inverse_depth_to_world(c.Ta.data(), c.sensor_a, lambda);
		EXPECT_LE((p - c.p).norm(), 1e-12 * std::max(1.0, c.p.norm())) << c.name;
		// λ → world → λ (θ ∈ (−π, π], φ ∈ (−π/2, π/2))
		const Eigen::Vector3d mu(rng.uniform(-M_PI, M_PI), rng.uniform(-1.5, 1.5), rng.uniform(0.05, 5));
		const Eigen::Vector3d back =
			world_to_inverse_depth(c.Ta.data(), c.sensor_a, inverse_depth_to_world(c.Ta.data(), c.sensor_a, mu));
		EXPECT_LE((back - mu).cwiseAbs().maxCoeff(), 1e-12 * std::max(1.0, mu[2])) << c.name;
		// CPose3D overloads agree with the storage ones.
		EXPECT_LE((inverse_depth_to_world(to_cpose(c.Ta), c.sensor_a, lambda) - p).norm(), 1e-12 * std::max(1.0, p.norm()));
	}
}

TEST(InverseDepthConversion, ReanchoringKeepsTheWorldPointAndRoundTrips)
{
	for (const auto& c : id_cases())
	{
		const Eigen::Vector3d lambda_a = world_to_inverse_depth(c.Ta.data(), c.sensor_a, c.p);
		const Eigen::Vector3d lambda_o = reanchor_inverse_depth(c.Ta.data(), c.sensor_a, c.To.data(), c.sensor_o, lambda_a);
		const Eigen::Vector3d p = inverse_depth_to_world(c.To.data(), c.sensor_o, lambda_o);
		EXPECT_LE((p - c.p).norm(), 1e-12 * std::max(1.0, c.p.norm())) << c.name;
		const Eigen::Vector3d back = reanchor_inverse_depth(c.To.data(), c.sensor_o, c.Ta.data(), c.sensor_a, lambda_o);
		EXPECT_LE((back - lambda_a).cwiseAbs().maxCoeff(), 1e-12) << c.name;
		// The re-anchored λ predicts the same measurement from any third pose.
		Rng rng(static_cast<unsigned>(c.name.size()));
		const Pose Tk = rng.pose();
		RangeBearingInverseDepthFactor fa({5.0, 0.1, 0.2}, c.sensor_o, c.sensor_a), fo({5.0, 0.1, 0.2}, c.sensor_o, c.sensor_o);
		EXPECT_LE((eval3(fa, {c.Ta.data(), Tk.data(), lambda_a.data()}) - eval3(fo, {c.To.data(), Tk.data(), lambda_o.data()}))
					  .cwiseAbs()
					  .maxCoeff(),
				  1e-10)
			<< c.name;
		// The CPose3D overload agrees.
		EXPECT_LE((reanchor_inverse_depth(to_cpose(c.Ta), c.sensor_a, to_cpose(c.To), c.sensor_o, lambda_a) - lambda_o)
					  .cwiseAbs()
					  .maxCoeff(),
				  1e-12);
	}
}

TEST(InverseDepthConversion, ThrowsWithAReason)
{
	const Pose T = make_pose(Eigen::Matrix3d::Identity(), Eigen::Vector3d(1, 2, 3));
	auto expect_message = [](auto&& fn, const std::string& needle) {
		try
		{
			fn();
			ADD_FAILURE() << "no exception; expected one mentioning '" << needle << "'";
		}
		catch (const std::invalid_argument& e)
		{
			EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
		}
	};
	expect_message([&] { inverse_depth_to_world(T.data(), CPose3D(), Eigen::Vector3d(0.1, 0.2, 0.0)); }, "rho must be > 0");
	expect_message([&] { inverse_depth_to_world(T.data(), CPose3D(), Eigen::Vector3d(0.1, 0.2, -1.0)); }, "rho must be > 0");
	expect_message([&] { inverse_depth_to_sensor_point(Eigen::Vector3d(NAN, 0.2, 1.0)); }, "non-finite");
	expect_message([&] { world_to_inverse_depth(T.data(), CPose3D(), Eigen::Vector3d(1, 2, 3)); }, "sensor's origin");
	expect_message([&] { world_to_inverse_depth(T.data(), CPose3D(), Eigen::Vector3d(1, INFINITY, 3)); }, "non-finite");
	expect_message([&] { inverse_depth_from_measurement({0.0, 0.1, 0.1}); }, "range must be > 0");
	expect_message(
		[&] {
			reanchor_inverse_depth(T.data(), CPose3D(), T.data(), CPose3D(), Eigen::Vector3d(0.1, 0.2, 0.0));
		},
		"rho must be > 0");
}
