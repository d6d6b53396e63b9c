#include <swba/factors/range_bearing.h>

#include <swba/core/lie.h>
#include <swba/core/manifold.h>

#include <array>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace swba
{
namespace
{
using Matrix36RowMajor = Eigen::Matrix<double, 3, 6, Eigen::RowMajor>;
using Matrix33RowMajor = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;

Eigen::Matrix3d rotation_of(const mrpt::poses::CPose3D& pose) { return pose.getRotationMatrix().asEigen(); }
Eigen::Vector3d translation_of(const mrpt::poses::CPose3D& pose) { return {pose.x(), pose.y(), pose.z()}; }

std::string vector_text(const Eigen::Vector3d& v)
{
	std::ostringstream os;
	os.precision(17);
	os << "[" << v[0] << ", " << v[1] << ", " << v[2] << "]";
	return os.str();
}

void check_measurement(const RangeBearingMeasurement& z, const char* who)
{
	if (!std::isfinite(z.range) || !std::isfinite(z.yaw) || !std::isfinite(z.pitch))
		throw std::invalid_argument(std::string(who) + ": measurement has a non-finite value");
	if (!(z.range > 0))
		throw std::invalid_argument(std::string(who) + ": range must be > 0, got " + std::to_string(z.range));
}

/** Unit direction m(θ, φ) = [cos φ cos θ, cos φ sin θ, −sin φ] and l_a = m/ρ with ∂l_a/∂λ. */
Eigen::Vector3d sensor_point_and_jacobian(const double* lambda, Eigen::Matrix3d* dl_dlambda)
{
	const double ct = std::cos(lambda[0]), st = std::sin(lambda[0]);
	const double cp = std::cos(lambda[1]), sp = std::sin(lambda[1]);
	const double inv_rho = 1.0 / lambda[2];
	const Eigen::Vector3d m(cp * ct, cp * st, -sp);
	if (dl_dlambda)
	{
		dl_dlambda->col(0) = Eigen::Vector3d(-cp * st, cp * ct, 0.0) * inv_rho;
		dl_dlambda->col(1) = Eigen::Vector3d(-sp * ct, -sp * st, -cp) * inv_rho;
		dl_dlambda->col(2) = -m * inv_rho * inv_rho;
	}
	return m * inv_rho;
}

bool valid_inverse_depth(const double* lambda)
{
	return std::isfinite(lambda[0]) && std::isfinite(lambda[1]) && std::isfinite(lambda[2]) && lambda[2] > 0;
}

/** l_a of a valid inverse depth λ (with ∂l_a/∂λ when asked); false for an invalid one (the factor fails). */
bool inverse_depth_point(const double* lambda, Eigen::Vector3d& la, Eigen::Matrix3d* dla)
{
	if (!valid_inverse_depth(lambda)) return false;
	la = sensor_point_and_jacobian(lambda, dla);
	return true;
}

/** An angle residual wrapped into (−π, π] as fmod(a − π, 2π) + π. Unlike wrap_to_pi (core/lie.h) this
 * rounds through ±π, so it can change the low bits of small residuals; it is kept so that the
 * estimates of the range-bearing estimators stay bit for bit what they have been. */
double wrap_angle_residual(double angle)
{
	// fmod(a − π, 2π) ∈ (−2π, 2π) → (−2π, 0] → + π ∈ (−π, π].
	double w = std::fmod(angle - M_PI, 2.0 * M_PI);
	if (w > 0) w -= 2.0 * M_PI;
	return w + M_PI;
}

/** Residual [h − z] with the angles wrapped. */
void write_residual(const Eigen::Vector3d& h, const RangeBearingMeasurement& z, double* residual)
{
	residual[0] = h[0] - z.range;
	residual[1] = wrap_angle_residual(h[1] - z.yaw);
	residual[2] = wrap_angle_residual(h[2] - z.pitch);
}

/** The residual of the sensor-frame point l against z, with ∂h/∂l when asked; false where the model
 * is undefined (range_bearing_model). */
bool model_residual(const Eigen::Vector3d& l, const RangeBearingMeasurement& z, double* residual, Eigen::Matrix3d* H)
{
	Eigen::Vector3d h;
	if (!range_bearing_model(l, h, H)) return false;
	write_residual(h, z, residual);
	return true;
}

/** ∂h/∂δT (row-major 3×6) for the observing pose T: ∂h/∂l·[−R_sᵀ, R_sᵀ[q]×], with HRsT = ∂h/∂l·R_sᵀ
 * and q the landmark in the robot frame. */
void write_observer_jacobian(const Eigen::Matrix3d& HRsT, const Eigen::Vector3d& q, double* jacobian)
{
	Eigen::Map<Matrix36RowMajor> J(jacobian);
	J.leftCols<3>() = -HRsT;
	J.rightCols<3>() = HRsT * skew(q);
}

std::array<double, SE3Manifold::kAmbient> storage_of(const mrpt::poses::CPose3D& pose)
{
	std::array<double, SE3Manifold::kAmbient> x;
	SE3Manifold::from_pose(pose, x.data());
	return x;
}
}  // namespace

bool range_bearing_model(const Eigen::Vector3d& l, Eigen::Vector3d& h, Eigen::Matrix3d* dh_dl)
{
	if (!l.allFinite()) return false;
	const double rxy2 = l.x() * l.x() + l.y() * l.y();
	const double rxy = std::sqrt(rxy2);
	if (!(rxy > 0)) return false;  // on the z axis (or at the origin): yaw undefined
	const double r2 = rxy2 + l.z() * l.z();
	const double r = std::sqrt(r2);
	// −asin(l.z/r) = −atan2(l.z, ‖l.xy‖); the latter keeps full precision near ±π/2.
	h << r, std::atan2(l.y(), l.x()), -std::atan2(l.z(), rxy);
	if (dh_dl)
	{
		dh_dl->row(0) = l.transpose() / r;
		dh_dl->row(1) << -l.y() / rxy2, l.x() / rxy2, 0.0;
		const double k = 1.0 / (r2 * rxy);
		dh_dl->row(2) << l.x() * l.z() * k, l.y() * l.z() * k, -rxy2 * k;
	}
	return h.allFinite();
}

// ---------------------------------------------------------------------------------------------
RangeBearingXyzFactor::RangeBearingXyzFactor(const RangeBearingMeasurement& measured,
											 const mrpt::poses::CPose3D& sensor_on_robot)
	: Factor(3, {SE3Manifold::kTangent, 3}),
	  z_(measured),
	  sensor_(sensor_on_robot),
	  Rs_(rotation_of(sensor_on_robot)),
	  ts_(translation_of(sensor_on_robot))
{
	check_measurement(measured, "RangeBearingXyzFactor");
}

bool RangeBearingXyzFactor::evaluate(const double* const* x, double* residual, double* const* jacobians) const
{
	const auto T = se3_view(x[0]);
	const Eigen::Matrix3d R = T.leftCols<3>();
	const Eigen::Map<const Eigen::Vector3d> p(x[1]);
	const Eigen::Vector3d q = R.transpose() * (p - T.col(3));  // landmark in the robot frame
	const Eigen::Vector3d l = Rs_.transpose() * (q - ts_);		// ... in the sensor frame
	const bool want_jacobians = jacobians && (jacobians[0] || jacobians[1]);
	Eigen::Matrix3d H;
	if (!model_residual(l, z_, residual, want_jacobians ? &H : nullptr)) return false;
	if (!want_jacobians) return true;
	const Eigen::Matrix3d HRsT = H * Rs_.transpose();
	if (jacobians[0]) write_observer_jacobian(HRsT, q, jacobians[0]);
	if (jacobians[1])
	{
		Eigen::Map<Matrix33RowMajor> J(jacobians[1]);
		J = HRsT * R.transpose();
	}
	return true;
}

// ---------------------------------------------------------------------------------------------
RangeBearingInverseDepthFactor::RangeBearingInverseDepthFactor(const RangeBearingMeasurement& measured,
															   const mrpt::poses::CPose3D& sensor_on_robot)
	: RangeBearingInverseDepthFactor(measured, sensor_on_robot, sensor_on_robot)
{
}

RangeBearingInverseDepthFactor::RangeBearingInverseDepthFactor(
	const RangeBearingMeasurement& measured, const mrpt::poses::CPose3D& sensor_on_robot,
	const mrpt::poses::CPose3D& anchor_sensor_on_robot)
	: Factor(3, {SE3Manifold::kTangent, SE3Manifold::kTangent, 3}),
	  z_(measured),
	  sensor_(sensor_on_robot),
	  anchor_sensor_(anchor_sensor_on_robot),
	  Rs_(rotation_of(sensor_on_robot)),
	  Rsa_(rotation_of(anchor_sensor_on_robot)),
	  ts_(translation_of(sensor_on_robot)),
	  tsa_(translation_of(anchor_sensor_on_robot))
{
	check_measurement(measured, "RangeBearingInverseDepthFactor");
}

bool RangeBearingInverseDepthFactor::evaluate(const double* const* x, double* residual,
											  double* const* jacobians) const
{
	const bool want_jacobians = jacobians && (jacobians[0] || jacobians[1] || jacobians[2]);
	Eigen::Vector3d la;
	Eigen::Matrix3d dla, H;
	if (!inverse_depth_point(x[2], la, want_jacobians ? &dla : nullptr)) return false;
	const auto Ta = se3_view(x[0]);
	const auto To = se3_view(x[1]);
	const Eigen::Matrix3d Ra = Ta.leftCols<3>(), Ro = To.leftCols<3>();
	const Eigen::Vector3d sa = Rsa_ * la + tsa_;				// anchor robot frame
	const Eigen::Vector3d p = Ra * sa + Ta.col(3);				// world
	const Eigen::Vector3d q = Ro.transpose() * (p - To.col(3));	// observing robot frame
	const Eigen::Vector3d l = Rs_.transpose() * (q - ts_);		// observing sensor frame
	if (!model_residual(l, z_, residual, want_jacobians ? &H : nullptr)) return false;
	if (!want_jacobians) return true;
	const Eigen::Matrix3d HRsT = H * Rs_.transpose();
	const Eigen::Matrix3d H_dp = HRsT * Ro.transpose() * Ra;  // ∂h/∂(anchor-robot-frame point)
	if (jacobians[0])
	{
		Eigen::Map<Matrix36RowMajor> J(jacobians[0]);
		J.leftCols<3>() = H_dp;
		J.rightCols<3>() = -H_dp * skew(sa);
	}
	if (jacobians[1]) write_observer_jacobian(HRsT, q, jacobians[1]);
	if (jacobians[2])
	{
		Eigen::Map<Matrix33RowMajor> J(jacobians[2]);
		J = H_dp * Rsa_ * dla;
	}
	return true;
}

// ---------------------------------------------------------------------------------------------
RangeBearingInverseDepthAnchorFactor::RangeBearingInverseDepthAnchorFactor(const RangeBearingMeasurement& measured)
	: Factor(3, {3}), z_(measured)
{
	check_measurement(measured, "RangeBearingInverseDepthAnchorFactor");
}

bool RangeBearingInverseDepthAnchorFactor::evaluate(const double* const* x, double* residual,
													double* const* jacobians) const
{
	const bool want_jacobians = jacobians && jacobians[0];
	Eigen::Vector3d la;
	Eigen::Matrix3d dla, H;
	if (!inverse_depth_point(x[0], la, want_jacobians ? &dla : nullptr)) return false;
	if (!model_residual(la, z_, residual, want_jacobians ? &H : nullptr)) return false;
	if (want_jacobians)
	{
		Eigen::Map<Matrix33RowMajor> J(jacobians[0]);
		J = H * dla;
	}
	return true;
}

// ---------------------------------------------------------------------------------------------
Eigen::Vector3d inverse_depth_to_sensor_point(const Eigen::Vector3d& lambda)
{
	if (!lambda.allFinite())
		throw std::invalid_argument("inverse depth " + vector_text(lambda) + " has a non-finite value");
	if (!(lambda[2] > 0))
		throw std::invalid_argument("inverse depth " + vector_text(lambda) +
									": inverse range rho must be > 0 (a point in front of its anchor)");
	return sensor_point_and_jacobian(lambda.data(), nullptr);
}

Eigen::Vector3d sensor_point_to_inverse_depth(const Eigen::Vector3d& l)
{
	if (!l.allFinite())
		throw std::invalid_argument("inverse depth of point " + vector_text(l) + ": non-finite coordinates");
	const double rxy = std::hypot(l.x(), l.y());
	const double r = std::hypot(rxy, l.z());
	if (!(r > 0))
		throw std::invalid_argument("inverse depth of point " + vector_text(l) +
									": the point is at the sensor's origin (range 0)");
	return {std::atan2(l.y(), l.x()), -std::atan2(l.z(), rxy), 1.0 / r};
}

Eigen::Vector3d inverse_depth_from_measurement(const RangeBearingMeasurement& z)
{
	check_measurement(z, "inverse_depth_from_measurement");
	return {z.yaw, z.pitch, 1.0 / z.range};
}

Eigen::Vector3d inverse_depth_to_world(const double* anchor_pose, const mrpt::poses::CPose3D& sensor_on_robot,
									   const Eigen::Vector3d& lambda)
{
	const auto Ta = se3_view(anchor_pose);
	if (!Ta.allFinite()) throw std::invalid_argument("inverse_depth_to_world: anchor pose is not finite");
	const Eigen::Vector3d la = inverse_depth_to_sensor_point(lambda);
	return Ta.leftCols<3>() * (rotation_of(sensor_on_robot) * la + translation_of(sensor_on_robot)) + Ta.col(3);
}

Eigen::Vector3d inverse_depth_to_world(const mrpt::poses::CPose3D& anchor_pose,
									   const mrpt::poses::CPose3D& sensor_on_robot, const Eigen::Vector3d& lambda)
{
	return inverse_depth_to_world(storage_of(anchor_pose).data(), sensor_on_robot, lambda);
}

Eigen::Vector3d world_to_inverse_depth(const double* anchor_pose, const mrpt::poses::CPose3D& sensor_on_robot,
									   const Eigen::Vector3d& p_world)
{
	const auto Ta = se3_view(anchor_pose);
	if (!Ta.allFinite()) throw std::invalid_argument("world_to_inverse_depth: anchor pose is not finite");
	const Eigen::Vector3d q = Ta.leftCols<3>().transpose() * (p_world - Ta.col(3));
	return sensor_point_to_inverse_depth(rotation_of(sensor_on_robot).transpose() *
										 (q - translation_of(sensor_on_robot)));
}

Eigen::Vector3d world_to_inverse_depth(const mrpt::poses::CPose3D& anchor_pose,
									   const mrpt::poses::CPose3D& sensor_on_robot, const Eigen::Vector3d& p_world)
{
	return world_to_inverse_depth(storage_of(anchor_pose).data(), sensor_on_robot, p_world);
}

Eigen::Vector3d reanchor_inverse_depth(const double* old_anchor, const mrpt::poses::CPose3D& old_sensor_on_robot,
									   const double* new_anchor, const mrpt::poses::CPose3D& new_sensor_on_robot,
									   const Eigen::Vector3d& lambda)
{
	return world_to_inverse_depth(new_anchor, new_sensor_on_robot,
								  inverse_depth_to_world(old_anchor, old_sensor_on_robot, lambda));
}

Eigen::Vector3d reanchor_inverse_depth(const mrpt::poses::CPose3D& old_anchor,
									   const mrpt::poses::CPose3D& old_sensor_on_robot,
									   const mrpt::poses::CPose3D& new_anchor,
									   const mrpt::poses::CPose3D& new_sensor_on_robot, const Eigen::Vector3d& lambda)
{
	return reanchor_inverse_depth(storage_of(old_anchor).data(), old_sensor_on_robot, storage_of(new_anchor).data(),
								  new_sensor_on_robot, lambda);
}
}  // namespace swba
