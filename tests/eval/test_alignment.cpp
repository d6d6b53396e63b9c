// Umeyama alignment (Eigen::umeyama wrapped), reflection handling, and evo's alignment modes.
#include <gtest/gtest.h>
#include <swba/eval/alignment.h>
#include <swba/eval/evaluation.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <random>

using namespace swba::eval;

namespace
{
Eigen::Matrix3Xd random_points(int n, unsigned seed)
{
	std::mt19937 rng(seed);
	std::uniform_real_distribution<double> u(-5.0, 5.0);
	Eigen::Matrix3Xd p(3, n);
	for (int i = 0; i < n; i++) p.col(i) << u(rng), u(rng), 0.3 * u(rng);
	return p;
}

/** Horn's closed-form quaternion solution of min Σ‖y − R x − t‖² over proper rotations — an independent
 * check (it can never return a reflection). */
Eigen::Matrix3d horn_rotation(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& y)
{
	const Eigen::Matrix3Xd xc = x.colwise() - x.rowwise().mean();
	const Eigen::Matrix3Xd yc = y.colwise() - y.rowwise().mean();
	const Eigen::Matrix3d M = xc * yc.transpose();	// Σ x yᵀ
	const double Sxx = M(0, 0), Sxy = M(0, 1), Sxz = M(0, 2), Syx = M(1, 0), Syy = M(1, 1), Syz = M(1, 2),
				 Szx = M(2, 0), Szy = M(2, 1), Szz = M(2, 2);
	Eigen::Matrix4d N;
	N << Sxx + Syy + Szz, Syz - Szy, Szx - Sxz, Sxy - Syx, Syz - Szy, Sxx - Syy - Szz, Sxy + Syx, Szx + Sxz,
		Szx - Sxz, Sxy + Syx, -Sxx + Syy - Szz, Syz + Szy, Sxy - Syx, Szx + Sxz, Syz + Szy, -Sxx - Syy + Szz;
	Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> es(N);
	const Eigen::Vector4d q = es.eigenvectors().col(3);
	return Eigen::Quaterniond(q(0), q(1), q(2), q(3)).normalized().toRotationMatrix();
}

Trajectory trajectory_from_points(const Eigen::Matrix3Xd& p, unsigned seed)
{
	std::mt19937 rng(seed);
	std::uniform_real_distribution<double> a(-M_PI, M_PI);
	Trajectory t;
	for (int i = 0; i < p.cols(); i++)
		t.push_back(i, mrpt::poses::CPose3D(p(0, i), p(1, i), p(2, i), a(rng), 0.3 * a(rng), 0.3 * a(rng)));
	return t;
}
}  // namespace

TEST(Umeyama, RecoversKnownSim3)
{
	const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
	const Eigen::Vector3d t(0.5, -2.0, 3.25);
	const double s = 1.3;
	const Eigen::Matrix3Xd src = random_points(50, 1);
	const Eigen::Matrix3Xd dst = ((s * R) * src).colwise() + t;
	const Sim3 a = umeyama_alignment(src, dst, true);
	EXPECT_NEAR(a.scale, 1.3, 1e-9);
	EXPECT_NEAR((a.R - R).norm(), 0.0, 1e-9);
	EXPECT_NEAR((a.t - t).norm(), 0.0, 1e-9);
	EXPECT_NEAR(a.R.determinant(), 1.0, 1e-12);
	// Without scale the rotation is still the best one and the scale is 1.
	const Sim3 b = umeyama_alignment(src, dst, false);
	EXPECT_EQ(b.scale, 1.0);
	EXPECT_NEAR((b.R - R).norm(), 0.0, 1e-9);
}

TEST(Umeyama, RecoversKnownSE3)
{
	const Eigen::Matrix3d R = Eigen::AngleAxisd(-2.5, Eigen::Vector3d(0, 1, 1).normalized()).toRotationMatrix();
	const Eigen::Vector3d t(10, 20, -30);
	const Eigen::Matrix3Xd src = random_points(10, 2);
	const Eigen::Matrix3Xd dst = (R * src).colwise() + t;
	const Sim3 a = umeyama_alignment(src, dst, false);
	EXPECT_NEAR((a.R - R).norm(), 0.0, 1e-9);
	EXPECT_NEAR((a.t - t).norm(), 0.0, 1e-9);
}

TEST(Umeyama, MirroredPlanarPointsGiveAProperRotation)
{
	// Points in the z = 0 plane mirrored in x: det U·det V < 0 in the SVD. The best proper rotation
	// (π about y) reproduces the mirror image exactly on this plane; a naive U·Vᵀ would be a reflection.
	Eigen::Matrix3Xd src = random_points(20, 3);
	src.row(2).setZero();
	Eigen::Matrix3Xd dst = src;
	dst.row(0) *= -1.0;
	const Sim3 a = umeyama_alignment(src, dst, true);
	EXPECT_NEAR(a.R.determinant(), 1.0, 1e-12);
	EXPECT_NEAR((a.R.transpose() * a.R - Eigen::Matrix3d::Identity()).norm(), 0.0, 1e-12);
	EXPECT_NEAR(a.scale, 1.0, 1e-9);
	const Eigen::Matrix3Xd mapped = ((a.scale * a.R) * src).colwise() + a.t;
	EXPECT_NEAR((mapped - dst).norm(), 0.0, 1e-9);
	const Eigen::Matrix3d Ry = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitY()).toRotationMatrix();
	EXPECT_NEAR((a.R - Ry).norm(), 0.0, 1e-9);
}

TEST(Umeyama, MirroredSpatialPointsMatchHornsProperRotation)
{
	const Eigen::Matrix3Xd src = random_points(30, 4);
	Eigen::Matrix3Xd dst = src;
	dst.row(1) *= -1.0;	 // a reflection: no rotation reproduces it
	const Sim3 a = umeyama_alignment(src, dst, false);
	EXPECT_NEAR(a.R.determinant(), 1.0, 1e-12);
	EXPECT_NEAR((a.R - horn_rotation(src, dst)).norm(), 0.0, 1e-9);
}

TEST(Umeyama, RejectsDegenerateInput)
{
	EXPECT_THROW(umeyama_alignment(Eigen::Matrix3Xd(3, 0), Eigen::Matrix3Xd(3, 0), false), std::invalid_argument);
	EXPECT_THROW(umeyama_alignment(Eigen::Matrix3Xd::Zero(3, 2), Eigen::Matrix3Xd::Zero(3, 3), false),
				 std::invalid_argument);
	// Scale from identical points is undefined (their cross-covariance is 0: degenerate).
	EXPECT_THROW(umeyama_alignment(Eigen::Matrix3Xd::Ones(3, 4), Eigen::Matrix3Xd::Random(3, 4), true),
				 std::invalid_argument);
	// One point determines a translation but no rotation: an error, as in evo (see below).
	Eigen::Matrix3Xd x(3, 1), y(3, 1);
	x << 1, 2, 3;
	y << 4, 4, 4;
	EXPECT_THROW(umeyama_alignment(x, y, false), std::invalid_argument);
}

TEST(AlignTrajectory, Sim3AlignmentUndoesAKnownTransformOfWholePoses)
{
	const Trajectory ref = trajectory_from_points(random_points(40, 5), 6);
	// est = A · ref with translations scaled: est_i = [R t] · [R_i, t_i / s]; aligning must bring it back.
	const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(0, 0, 1)).toRotationMatrix();
	const Eigen::Vector3d t(1, 2, 3);
	const double s = 1.3;
	Trajectory est = ref;
	for (auto& p : est.poses)
	{
		Eigen::Matrix4d T = to_matrix(p);
		T.topRightCorner<3, 1>() /= s;
		Eigen::Matrix4d A = Eigen::Matrix4d::Identity();
		A.topLeftCorner<3, 3>() = R.transpose();
		A.topRightCorner<3, 1>() = -R.transpose() * t;
		p = from_matrix(A * T);
	}
	ApeOptions o;
	o.relation = PoseRelation::FullTransformation;
	o.alignment.align = o.alignment.correct_scale = true;
	const MetricResult r = compute_ape(ref, est, o);
	EXPECT_NEAR(r.alignment.transform.scale, s, 1e-9);
	EXPECT_NEAR(r.stats.max, 0.0, 1e-9);
	// Without scale correction the error cannot vanish.
	o.alignment.correct_scale = false;
	EXPECT_GT(compute_ape(ref, est, o).stats.rmse, 1e-3);
}

TEST(AlignTrajectory, ScaleOnlyKeepsOrientationAndScalesPositions)
{
	const Trajectory ref = trajectory_from_points(random_points(20, 7), 8);
	Trajectory est = ref;
	for (auto& p : est.poses) p = mrpt::poses::CPose3D::FromRotationAndTranslation(
								  p.getRotationMatrix().asEigen(), Eigen::Vector3d(p.x() / 2, p.y() / 2, p.z() / 2));
	AlignmentOptions o;
	o.correct_scale = true;
	Trajectory aligned = est;
	const AlignmentResult a = align_trajectory(aligned, ref, o);
	EXPECT_NEAR(a.transform.scale, 2.0, 1e-9);
	EXPECT_EQ(a.transform.R, Eigen::Matrix3d::Identity());
	for (std::size_t i = 0; i < ref.size(); i++)
		EXPECT_NEAR((to_matrix(aligned.poses[i]) - to_matrix(ref.poses[i])).norm(), 0.0, 1e-9);
	EXPECT_EQ(alignment_title(o), "(scale corrected)");
}

TEST(AlignTrajectory, OriginAlignmentMapsFirstPoseOntoReference)
{
	const Trajectory ref = trajectory_from_points(random_points(5, 9), 10);
	Trajectory est = trajectory_from_points(random_points(5, 11), 12);
	AlignmentOptions o;
	o.align_origin = true;
	align_trajectory(est, ref, o);
	EXPECT_NEAR((to_matrix(est.poses[0]) - to_matrix(ref.poses[0])).norm(), 0.0, 1e-12);
	EXPECT_EQ(alignment_title(o), "(with origin alignment)");
	o.align = true;
	EXPECT_EQ(alignment_title(o), "(with SE(3) Umeyama alignment)\n(with origin alignment)");
	EXPECT_EQ(alignment_title({}), "(not aligned)");
}

TEST(Umeyama, OneOrTwoPosesOrCollinearOnesAreDegenerateAsInEvo)
{
	Eigen::Matrix3Xd one(3, 1), two(3, 2), line(3, 4);
	one << 1, 2, 3;
	two << 0, 1, 0, 0, 0, 0;
	line << 0, 1, 2, 3, 0, 0, 0, 0, 0, 0, 0, 0;
	for (const Eigen::Matrix3Xd* pts : {&one, &two, &line})
		for (const bool scale : {false, true})
		{
			try
			{
				umeyama_alignment(*pts, *pts, scale);
				ADD_FAILURE() << pts->cols() << " points, scale " << scale << ": no error";
			}
			catch (const std::invalid_argument& e)
			{
				EXPECT_EQ(std::string(e.what()).rfind("Degenerate covariance rank, Umeyama alignment is not possible", 0), 0u)
					<< e.what();
			}
		}
	// Three points that span a plane are enough.
	Eigen::Matrix3Xd plane(3, 3);
	plane << 0, 1, 0, 0, 0, 1, 0, 0, 0;
	EXPECT_NO_THROW(umeyama_alignment(plane, plane, false));
}

TEST(YawAlignment, RecoversAKnownYawAndTranslationAndIsTheBestOneUnderNoise)
{
	const Eigen::Matrix3d R = Eigen::AngleAxisd(2.9, Eigen::Vector3d::UnitZ()).toRotationMatrix();
	const Eigen::Vector3d t(3, -4, 1.5);
	const Eigen::Matrix3Xd src = random_points(40, 3);
	const Sim3 a = yaw_alignment(src, (R * src).colwise() + t);
	EXPECT_NEAR((a.R - R).norm(), 0.0, 1e-12);
	EXPECT_NEAR((a.t - t).norm(), 0.0, 1e-12);
	EXPECT_EQ(a.scale, 1.0);
	// With noise, no other yaw (nor translation, which then follows from the centroids) does better.
	const Eigen::Matrix3Xd dst = ((R * src).colwise() + t) + 0.3 * random_points(40, 4);
	auto cost = [&](const Eigen::Matrix3d& Ry, const Eigen::Vector3d& ty) {
		return (((Ry * src).colwise() + ty) - dst).squaredNorm();
	};
	const Sim3 b = yaw_alignment(src, dst);
	for (double dyaw : {-1e-3, 1e-3})
	{
		const Eigen::Matrix3d Ry = Eigen::AngleAxisd(dyaw, Eigen::Vector3d::UnitZ()).toRotationMatrix() * b.R;
		const Eigen::Vector3d ty = dst.rowwise().mean() - Ry * src.rowwise().mean();
		EXPECT_GT(cost(Ry, ty), cost(b.R, b.t));
	}
	EXPECT_THROW(yaw_alignment(Eigen::Matrix3Xd::Zero(3, 3), Eigen::Matrix3Xd::Zero(3, 3)), std::invalid_argument);
	EXPECT_THROW(yaw_alignment(src, src.leftCols(3)), std::invalid_argument);
}
