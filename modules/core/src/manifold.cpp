#include <swba/core/manifold.h>

#include <mrpt/poses/Lie/SO.h>

#include <Eigen/Geometry>
#include <array>
#include <mutex>
#include <stdexcept>

namespace swba
{
EuclideanManifold::EuclideanManifold(int n) : n_(n)
{
	if (n <= 0) throw std::invalid_argument("EuclideanManifold: dimension must be positive");
}

void EuclideanManifold::plus(const double* x, const double* delta, double* x_plus) const
{
	for (int i = 0; i < n_; i++) x_plus[i] = x[i] + delta[i];
}

void EuclideanManifold::minus(const double* y, const double* x, double* delta) const
{
	for (int i = 0; i < n_; i++) delta[i] = y[i] - x[i];
}

std::shared_ptr<const EuclideanManifold> euclidean_manifold(int n)
{
	static std::array<std::shared_ptr<const EuclideanManifold>, 17> cache;
	static std::mutex mtx;
	if (n <= 0 || n > 16) return std::make_shared<EuclideanManifold>(n);
	std::lock_guard<std::mutex> lock(mtx);
	if (!cache[n]) cache[n] = std::make_shared<EuclideanManifold>(n);
	return cache[n];
}

std::shared_ptr<const SE3Manifold> SE3Manifold::instance()
{
	static const auto inst = std::make_shared<const SE3Manifold>();
	return inst;
}

void SE3Manifold::plus(const double* x, const double* delta, double* x_plus) const
{
	const auto T = se3_view(x);
	const Eigen::Matrix3d R = T.leftCols<3>();
	const Eigen::Vector3d t = T.col(3);
	mrpt::math::CVectorFixedDouble<3> w;
	for (int i = 0; i < 3; i++) w[i] = delta[3 + i];
	const Eigen::Matrix3d dR = mrpt::poses::Lie::SO<3>::exp(w).asEigen();
	// Re-orthonormalise through a unit quaternion so that rounding never accumulates.
	const Eigen::Matrix3d Rn =
		Eigen::Quaterniond(R * dR).normalized().toRotationMatrix();
	const Eigen::Vector3d tn = t + R * Eigen::Vector3d(delta[0], delta[1], delta[2]);
	auto out = se3_view(x_plus);
	out.leftCols<3>() = Rn;
	out.col(3) = tn;
}

void SE3Manifold::minus(const double* y, const double* x, double* delta) const
{
	const auto X = se3_view(x);
	const auto Y = se3_view(y);
	const Eigen::Matrix3d Rx = X.leftCols<3>();
	const Eigen::Matrix3d dR = Rx.transpose() * Y.leftCols<3>();
	const Eigen::Vector3d rho = Rx.transpose() * (Y.col(3) - X.col(3));
	// Rotation log through a unit quaternion (Eigen::AngleAxisd): accurate up to and at π, where
	// MRPT 2.5's SO<3>::log rounds angles within ~1e-7 of π to π.
	const Eigen::AngleAxisd aa(Eigen::Quaterniond(dR).normalized());
	const Eigen::Vector3d w = aa.angle() * aa.axis();
	for (int i = 0; i < 3; i++)
	{
		delta[i] = rho[i];
		delta[3 + i] = w[i];
	}
}

void SE3Manifold::from_pose(const mrpt::poses::CPose3D& pose, double* x)
{
	auto out = se3_view(x);
	out.leftCols<3>() = pose.getRotationMatrix().asEigen();
	out.col(3) = Eigen::Vector3d(pose.x(), pose.y(), pose.z());
}

mrpt::poses::CPose3D SE3Manifold::to_pose(const double* x)
{
	const auto T = se3_view(x);
	return to_pose(T.leftCols<3>(), T.col(3));
}

mrpt::poses::CPose3D SE3Manifold::to_pose(const Eigen::Matrix3d& R, const Eigen::Vector3d& t)
{
	mrpt::math::CMatrixDouble33 M;
	M.asEigen() = R;
	return mrpt::poses::CPose3D(M, mrpt::math::CVectorFixedDouble<3>({t.x(), t.y(), t.z()}));
}
}  // namespace swba
