// The EKF's covariances in the window's tangent convention: the Jacobian from MRPT's quaternion pose
// parameters to the right perturbation, checked numerically, and the covariances of a short run.
#include <gtest/gtest.h>
#include <swba/estimators/ekf_slam.h>

#include "window_test_utils.h"

#include <mrpt/poses/Lie/SO.h>

#include <Eigen/Dense>

using namespace swba;
using namespace swba::estimators;

namespace
{
/** δ of the pose with parameters p = (x, y, z, qr, qx, qy, qz) (q normalised) relative to `mean`:
 * ρ = R̂ᵀ(t − t̂), ω = Log(R̂ᵀ R). */
Eigen::Matrix<double, 6, 1> tangent_of(const mrpt::poses::CPose3DQuat& mean, const Eigen::Matrix<double, 7, 1>& p)
{
	mrpt::math::CQuaternionDouble q(p[3], p[4], p[5], p[6]);
	q.normalize();
	mrpt::math::CMatrixDouble33 R, Rm;
	q.rotationMatrixNoResize(R);
	mean.quat().rotationMatrixNoResize(Rm);
	Eigen::Matrix<double, 6, 1> d;
	const Eigen::Vector3d t(p[0], p[1], p[2]), tm(mean.x(), mean.y(), mean.z());
	d.head<3>() = Rm.asEigen().transpose() * (t - tm);
	const mrpt::math::CMatrixDouble33 dR(Rm.asEigen().transpose() * R.asEigen());
	const auto w = mrpt::poses::Lie::SO<3>::log(dR);
	d.tail<3>() = Eigen::Vector3d(w[0], w[1], w[2]);
	return d;
}
}  // namespace

TEST(EkfCovariance, QuaternionToTangentJacobianMatchesCentralDifferences)
{
	for (const auto& pose : {mrpt::poses::CPose3D(1, -2, 0.5, 0.3, -0.2, 0.1), mrpt::poses::CPose3D(0, 0, 0, 3.0, 1.2, -2.5),
							 mrpt::poses::CPose3D(-4, 2, 1, 1e-5, 0, 0)})
	{
		const mrpt::poses::CPose3DQuat mean(pose);
		Eigen::Matrix<double, 7, 1> p0;
		for (int i = 0; i < 7; i++) p0[i] = mean[i];
		Eigen::Matrix<double, 6, 7> num;
		const double h = 1e-6;
		for (int i = 0; i < 7; i++)
		{
			Eigen::Matrix<double, 7, 1> a = p0, b = p0;
			a[i] += h;
			b[i] -= h;
			num.col(i) = (tangent_of(mean, a) - tangent_of(mean, b)) / (2 * h);
		}
		const Eigen::Matrix<double, 6, 7> J = quaternion_to_tangent_jacobian(mean);
		EXPECT_LT((J - num).norm(), 1e-8) << pose;
		// Blind to the quaternion's norm direction.
		EXPECT_LT((J.rightCols<4>() * p0.tail<4>()).norm(), 1e-12);
	}
}

TEST(EkfCovariance, EveryPoseAndLandmarkHasAPositiveDefiniteCovariance)
{
	EkfSlamOptions o;
	o.max_steps = 20;
	const EkfSlamResult r = run_ekf_slam(test::demo_rawlog().steps, o);
	ASSERT_FALSE(r.failed);
	ASSERT_EQ(r.covariances.size(), r.poses.size());
	// The first step has no odometry: the filter is still at its exact start (zero covariance).
	EXPECT_EQ(r.covariances[0].norm(), 0);
	for (std::size_t i = 1; i < r.covariances.size(); i++)
		EXPECT_GT(Eigen::SelfAdjointEigenSolver<PoseCovariance>(r.covariances[i]).eigenvalues().minCoeff(), 0) << i;
	ASSERT_EQ(r.landmarks_final.size(), r.landmarks);
	for (const auto& [id, l] : r.landmarks_final)
		EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(l.covariance).eigenvalues().minCoeff(), 0) << id;
}
