#include <swba/io/rawlog.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <stdexcept>

namespace swba::io
{
Eigen::Matrix<double, 6, 6> ypr_to_tangent_jacobian(const mrpt::poses::CPose3D& mean)
{
	// Z⁻¹·Z(ypr + d) = (Rᵀ R(angles + d_a), Rᵀ d_t): the pseudo-log's ρ is Rᵀ d_t, and ω = Log(Rᵀ R')
	// is, to first order, the body-frame angular velocity of R = Rz(yaw) Ry(pitch) Rx(roll).
	const double p = mean.pitch(), r = mean.roll();
	const double sp = std::sin(p), cp = std::cos(p), sr = std::sin(r), cr = std::cos(r);
	Eigen::Matrix<double, 6, 6> J = Eigen::Matrix<double, 6, 6>::Zero();
	J.topLeftCorner<3, 3>() = mean.getRotationMatrix().asEigen().transpose();
	J.bottomRightCorner<3, 3>() << -sp, 0.0, 1.0,  //
		cp * sr, cr, 0.0,  //
		cp * cr, -sr, 0.0;
	return J;
}

Eigen::Matrix<double, 6, 6> odometry_tangent_covariance(const mrpt::poses::CPose3DPDFGaussian& odometry)
{
	const Eigen::Matrix<double, 6, 6> J = ypr_to_tangent_jacobian(odometry.mean);
	const Eigen::Matrix<double, 6, 6> S = J * odometry.cov.asEigen() * J.transpose();
	return 0.5 * (S + S.transpose());
}

Eigen::Matrix<double, 6, 6> odometry_information(
	const mrpt::poses::CPose3DPDFGaussian& odometry, const OdometryInformationOptions& options)
{
	if (!(options.min_sigma_translation > 0) || !(options.min_sigma_rotation > 0) ||
		!std::isfinite(options.min_sigma_translation) || !std::isfinite(options.min_sigma_rotation))
		throw std::invalid_argument("odometry_information: the sigma floors must be finite and > 0");
	const Eigen::Matrix<double, 6, 6> cov = odometry_tangent_covariance(odometry);
	if (!cov.allFinite()) throw std::invalid_argument("odometry_information: the odometry is not finite");

	Eigen::Matrix<double, 6, 1> s;
	s << Eigen::Vector3d::Constant(options.min_sigma_translation), Eigen::Vector3d::Constant(options.min_sigma_rotation);
	const Eigen::Matrix<double, 6, 1> inv_s = s.cwiseInverse();
	// Floor in the σ_min-scaled space, where the floor is the identity.
	const Eigen::Matrix<double, 6, 6> A = inv_s.asDiagonal() * cov * inv_s.asDiagonal();
	Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> es(0.5 * (A + A.transpose()));
	if (es.info() != Eigen::Success) throw std::invalid_argument("odometry_information: eigen-decomposition failed");
	const Eigen::Matrix<double, 6, 1> inv_lambda = es.eigenvalues().cwiseMax(1.0).cwiseInverse();
	const Eigen::Matrix<double, 6, 6> Ainv =
		es.eigenvectors() * inv_lambda.asDiagonal() * es.eigenvectors().transpose();
	Eigen::Matrix<double, 6, 6> info = inv_s.asDiagonal() * Ainv * inv_s.asDiagonal();
	return 0.5 * (info + info.transpose());
}

IniKeys<OdometryInformationOptions> OdometryInformationOptions::ini_keys(const std::string& section)
{
	using O = OdometryInformationOptions;
	return {ini::number_key<O>(section, "min_sigma_translation_m", "m",
							   "floor of the odometry's translational standard deviations", &O::min_sigma_translation,
							   ini::parse_positive),
			ini::number_key<O>(section, "min_sigma_rotation_rad", "rad",
							   "floor of the odometry's rotational standard deviations", &O::min_sigma_rotation,
							   ini::parse_positive)};
}
}  // namespace swba::io
