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

namespace
{
/** The information of covariance `cov` floored in the σ_min-scaled space (S = diag(floors)): every
 * eigenvalue of S⁻¹ Σ S⁻¹ raised to at least 1. */
template <int N>
Eigen::Matrix<double, N, N> floored_information(const Eigen::Matrix<double, N, N>& cov,
												const Eigen::Matrix<double, N, 1>& floors)
{
	if (!cov.allFinite()) throw std::invalid_argument("odometry_information: the odometry is not finite");
	const Eigen::Matrix<double, N, 1> inv_s = floors.cwiseInverse();
	const Eigen::Matrix<double, N, N> A = inv_s.asDiagonal() * cov * inv_s.asDiagonal();
	Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, N, N>> es(0.5 * (A + A.transpose()));
	if (es.info() != Eigen::Success) throw std::invalid_argument("odometry_information: eigen-decomposition failed");
	const Eigen::Matrix<double, N, 1> inv_lambda = es.eigenvalues().cwiseMax(1.0).cwiseInverse();
	const Eigen::Matrix<double, N, N> Ainv = es.eigenvectors() * inv_lambda.asDiagonal() * es.eigenvectors().transpose();
	const Eigen::Matrix<double, N, N> info = inv_s.asDiagonal() * Ainv * inv_s.asDiagonal();
	return 0.5 * (info + info.transpose());
}

void check_floors(const OdometryInformationOptions& options)
{
	if (!(options.min_sigma_translation > 0) || !(options.min_sigma_rotation > 0) ||
		!std::isfinite(options.min_sigma_translation) || !std::isfinite(options.min_sigma_rotation))
		throw std::invalid_argument("odometry_information: the sigma floors must be finite and > 0");
}
}  // namespace

Eigen::Matrix<double, 6, 6> odometry_information(
	const mrpt::poses::CPose3DPDFGaussian& odometry, const OdometryInformationOptions& options)
{
	check_floors(options);
	Eigen::Matrix<double, 6, 1> s;
	s << Eigen::Vector3d::Constant(options.min_sigma_translation), Eigen::Vector3d::Constant(options.min_sigma_rotation);
	return floored_information<6>(odometry_tangent_covariance(odometry), s);
}

Eigen::Matrix3d planar_odometry_information(const mrpt::poses::CPose3DPDFGaussian& odometry,
											const OdometryInformationOptions& options)
{
	check_floors(options);
	const Eigen::Matrix<double, 6, 6> cov = odometry_tangent_covariance(odometry);
	constexpr int kPlanar[3] = {0, 1, 5};  // ρx, ρy, ωz
	Eigen::Matrix3d c;
	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++) c(i, j) = cov(kPlanar[i], kPlanar[j]);
	const Eigen::Vector3d s(options.min_sigma_translation, options.min_sigma_translation, options.min_sigma_rotation);
	return floored_information<3>(c, s);
}

bool is_planar_step(const RawlogStep& step)
{
	if (step.has_odometry && !step.odometry_is_2d) return false;
	for (const auto& r : step.readings)
		if (r.pitch != 0.0) return false;
	return true;
}

bool is_planar(const std::vector<RawlogStep>& steps)
{
	bool odometry = false;
	for (const auto& s : steps)
	{
		if (!is_planar_step(s)) return false;
		odometry = odometry || s.has_odometry;
	}
	return odometry;
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
