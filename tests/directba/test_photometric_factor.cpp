// PhotometricPatchFactor: bilinear sampling against hand-computed values, analytic Jacobians against
// central differences through the manifolds, and the image-border / behind-camera handling.
#include <swba/core/manifold.h>
#include <swba/core/numeric_diff.h>
#include <swba/factors/photometric_patch.h>

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

using namespace swba;

namespace
{
// 4×3 image with pixel values chosen so that every interpolation is easy to do by hand:
//   row 0:  10  20  40  80
//   row 1:  30  50  70  90
//   row 2: 100 110 120 130
std::shared_ptr<IntensityImage> tiny_image()
{
	auto img = std::make_shared<IntensityImage>(4, 3);
	const float v[12] = {10, 20, 40, 80, 30, 50, 70, 90, 100, 110, 120, 130};
	for (int i = 0; i < 12; i++) img->pixels[size_t(i)] = v[i];
	return img;
}

// A smooth image (sum of sinusoids, not quantised) so that the bilinear interpolant has
// well-defined non-zero gradients everywhere.
std::shared_ptr<IntensityImage> smooth_image(int w, int h)
{
	auto img = std::make_shared<IntensityImage>(w, h);
	for (int r = 0; r < h; r++)
		for (int c = 0; c < w; c++)
			img->at(c, r) = static_cast<float>(120 + 40 * std::sin(0.21 * c + 0.05 * r) +
											   30 * std::cos(0.17 * r - 0.08 * c) + 10 * std::sin(0.5 * c + 0.4 * r));
	return img;
}

/** The shipped data set's intrinsics, io::directba_dataset_intrinsics() (swba_io is not linked into this
 * test's ASan build, tests/directba/tests.cmake). */
PatchCameraIntrinsics shipped_dataset_K() { return {277.34, 291.402, 312.234, 239.777}; }

PatchValues some_patch()
{
	PatchValues p;
	for (int k = 0; k < kPatchSize; k++) p[k] = 90.0 + 3.0 * k;
	return p;
}

double frac(double x) { return x - std::floor(x); }
}  // namespace

TEST(DirectBABilinear, HandComputedValuesAndGradients)
{
	const auto img = tiny_image();
	BilinearSample s;
	// At a pixel centre: the pixel value.
	ASSERT_TRUE(sample_bilinear(*img, 1.0, 1.0, s));
	EXPECT_DOUBLE_EQ(s.value, 50.0);
	// Half-way between (1,0)=20 and (2,0)=40.
	ASSERT_TRUE(sample_bilinear(*img, 1.5, 0.0, s));
	EXPECT_DOUBLE_EQ(s.value, 30.0);
	EXPECT_DOUBLE_EQ(s.du, 20.0);
	EXPECT_DOUBLE_EQ(s.dv, 0.5 * (50 - 20) + 0.5 * (70 - 40));  // 30
	// (0.25, 0.5): cell (0,0)-(1,1) with a = 0.25, b = 0.5:
	// 0.75·0.5·10 + 0.25·0.5·20 + 0.75·0.5·30 + 0.25·0.5·50 = 3.75 + 2.5 + 11.25 + 6.25 = 23.75
	ASSERT_TRUE(sample_bilinear(*img, 0.25, 0.5, s));
	EXPECT_DOUBLE_EQ(s.value, 23.75);
	EXPECT_DOUBLE_EQ(s.du, 0.5 * (20 - 10) + 0.5 * (50 - 30));  // 15
	EXPECT_DOUBLE_EQ(s.dv, 0.75 * (30 - 10) + 0.25 * (50 - 20));  // 22.5
	// (2.6, 1.3): cell (2,1)-(3,2): a = 0.6, b = 0.3: 0.4·0.7·70 + 0.6·0.7·90 + 0.4·0.3·120 + 0.6·0.3·130
	ASSERT_TRUE(sample_bilinear(*img, 2.6, 1.3, s));
	EXPECT_NEAR(s.value, 19.6 + 37.8 + 14.4 + 23.4, 1e-12);
	EXPECT_NEAR(s.du, 0.7 * (90 - 70) + 0.3 * (130 - 120), 1e-12);
	EXPECT_NEAR(s.dv, 0.4 * (120 - 70) + 0.6 * (130 - 90), 1e-12);
}

TEST(DirectBABilinear, RefusesFootprintsOutsideTheImage)
{
	const auto img = tiny_image();
	BilinearSample s;
	s.value = -1;
	// The last column/row has no right/lower neighbour: sampling there would read outside.
	EXPECT_FALSE(sample_bilinear(*img, 3.0, 1.0, s));
	EXPECT_FALSE(sample_bilinear(*img, 1.0, 2.0, s));
	EXPECT_FALSE(sample_bilinear(*img, -0.001, 1.0, s));
	EXPECT_FALSE(sample_bilinear(*img, 1.0, -1e-9, s));
	EXPECT_FALSE(sample_bilinear(*img, std::nan(""), 1.0, s));
	EXPECT_FALSE(sample_bilinear(*img, 1.0, std::numeric_limits<double>::infinity(), s));
	EXPECT_EQ(s.value, -1);  // untouched
	EXPECT_TRUE(sample_bilinear(*img, 2.999, 1.999, s));
	EXPECT_TRUE(sample_bilinear(*img, 0.0, 0.0, s));
}

TEST(DirectBAFactor, JacobiansMatchNumericAwayFromPixelBorders)
{
	const auto img = smooth_image(640, 480);
	const auto K = shipped_dataset_K();
	const PhotometricPatchFactor f(some_patch(), img, K);
	const auto se3 = SE3Manifold::instance();
	const auto r3 = euclidean_manifold(3);
	std::mt19937 rng(3);
	std::uniform_real_distribution<double> U(-1, 1);
	int tested = 0;
	for (int trial = 0; trial < 200 && tested < 40; trial++)
	{
		// A camera somewhere, a point 2..6 in front of it.
		const Eigen::Matrix3d R =
			Eigen::AngleAxisd(0.5 * U(rng), Eigen::Vector3d(U(rng), U(rng), U(rng)).normalized()).toRotationMatrix();
		const Eigen::Vector3d t(U(rng), U(rng), U(rng));
		double pose[12];
		auto T = se3_view(pose);
		T.leftCols<3>() = R;
		T.col(3) = t;
		const Eigen::Vector3d pc(1.5 * U(rng), 1.2 * U(rng), 4.0 + 2.0 * U(rng));
		const Eigen::Vector3d pw = R * pc + t;
		double u, v;
		ASSERT_TRUE(f.project(pose, pw.data(), u, v));
		if (!f.patch_inside(u, v)) continue;
		// Away from pixel borders: the bilinear interpolant is smooth only inside a cell
		// (all 16 samples share the fractional part of (u, v)).
		if (frac(u) < 0.02 || frac(u) > 0.98 || frac(v) < 0.02 || frac(v) > 0.98) continue;
		const auto cmp = compare_jacobians(f, {pose, pw.data()}, {se3.get(), r3.get()}, 1e-6);
		EXPECT_LE(cmp.max_relative_error(), 1e-6) << "trial " << trial << " at (" << u << ", " << v << ")";
		// The Jacobian must not be trivially zero.
		EXPECT_GT(cmp.analytic[0].cwiseAbs().maxCoeff(), 1.0);
		EXPECT_GT(cmp.analytic[1].cwiseAbs().maxCoeff(), 1.0);
		tested++;
	}
	EXPECT_GE(tested, 20);
}

TEST(DirectBAFactor, ResidualIsHostPatchMinusBilinearSamplesInSeedOrder)
{
	const auto img = smooth_image(64, 48);
	PatchCameraIntrinsics K;
	K.fx = K.fy = 50;
	K.cx = 30;
	K.cy = 20;
	const PatchValues patch = some_patch();
	const PhotometricPatchFactor f(patch, img, K);
	double pose[12];
	SE3Manifold::from_pose(mrpt::poses::CPose3D(), pose);
	// Point projecting to (u, v) = (30 + 50·0.1/2, 20 + 50·(−0.05)/2) = (32.5, 18.75).
	const double pw[3] = {0.1, -0.05, 2.0};
	double r[16];
	const double* x[2] = {pose, pw};
	ASSERT_TRUE(f.evaluate(x, r, nullptr));
	for (int k = 0; k < 16; k++)
	{
		const int dx = k / 4 - 2, dy = k % 4 - 2;  // dx outer, dy inner (directBA.cpp's loop order)
		BilinearSample s;
		ASSERT_TRUE(sample_bilinear(*img, 32.5 + dx, 18.75 + dy, s));
		EXPECT_NEAR(r[k], patch[k] - s.value, 1e-9) << "k=" << k;
	}
}

TEST(DirectBAFactor, BorderRuleMatchesBruteForceAndNeverReadsOutside)
{
	// A small image whose buffer is exactly width×height floats: under ASan any read outside
	// fails the test run. Projections are swept across and beyond the whole image.
	for (int border : {0, 1, 3})
	{
		const auto img = smooth_image(16, 14);
		PatchCameraIntrinsics K;
		K.fx = K.fy = 8;  // a power of two: u/fx·fx == u exactly, so the boundary cases are exact
		K.cx = K.cy = 0;
		PhotometricPatchFactor::Options o;
		o.border = border;
		const PhotometricPatchFactor f(some_patch(), img, K, o);
		double pose[12];
		SE3Manifold::from_pose(mrpt::poses::CPose3D(), pose);
		int inside = 0, outside = 0;
		for (double u = -6.0; u <= 22.0; u += 0.125)
			for (double v = -6.0; v <= 20.0; v += 0.125)
			{
				// Point at depth 1 projecting exactly to (u, v).
				const double pw[3] = {u / K.fx, v / K.fy, 1.0};
				double r[16], J0[16 * 6], J1[16 * 3];
				double* jac[2] = {J0, J1};
				const double* x[2] = {pose, pw};
				const bool ok = f.evaluate(x, r, jac);
				// Brute force: every bilinear neighbour of every sample within [border, size−1−border].
				bool expected = true;
				for (int k = 0; k < 16; k++)
				{
					const double su = u + patch_offset_x(k), sv = v + patch_offset_y(k);
					const double x0 = std::floor(su), y0 = std::floor(sv);
					expected = expected && x0 >= border && y0 >= border && x0 + 1 <= img->width - 1 - border &&
							   y0 + 1 <= img->height - 1 - border;
				}
				EXPECT_EQ(ok, expected) << "border " << border << " u " << u << " v " << v;
				(ok ? inside : outside)++;
			}
		EXPECT_GT(inside, 0) << "border " << border;
		EXPECT_GT(outside, 0);
	}
}

TEST(DirectBAFactor, PointBehindOrOnTheCameraPlaneIsDropped)
{
	const auto img = smooth_image(640, 480);
	const PhotometricPatchFactor f(some_patch(), img, shipped_dataset_K());
	double pose[12];
	SE3Manifold::from_pose(mrpt::poses::CPose3D(), pose);
	double r[16];
	for (double z : {-3.0, -1e-3, 0.0, 1e-9})
	{
		const double pw[3] = {0.0, 0.0, z};
		const double* x[2] = {pose, pw};
		EXPECT_FALSE(f.evaluate(x, r, nullptr)) << "z = " << z;
	}
	// A camera turned around sees the same point behind it.
	const double pw[3] = {0.0, 0.0, 3.0};
	const double* x[2] = {pose, pw};
	EXPECT_TRUE(f.evaluate(x, r, nullptr));
	SE3Manifold::from_pose(mrpt::poses::CPose3D(0, 0, 0, 0, M_PI, 0), pose);  // pitch 180°
	EXPECT_FALSE(f.evaluate(x, r, nullptr));
}

TEST(DirectBAFactor, PoseIsWorldFromCamera)
{
	// A camera at (1, 0, 0) looking along +z sees the world point (1, 0, 5) at the principal point.
	const auto img = smooth_image(640, 480);
	const auto K = shipped_dataset_K();
	const PhotometricPatchFactor f(some_patch(), img, K);
	double pose[12];
	SE3Manifold::from_pose(mrpt::poses::CPose3D(1, 0, 0, 0, 0, 0), pose);
	const double pw[3] = {1.0, 0.0, 5.0};
	double u, v;
	ASSERT_TRUE(f.project(pose, pw, u, v));
	EXPECT_NEAR(u, K.cx, 1e-12);
	EXPECT_NEAR(v, K.cy, 1e-12);
}

TEST(DirectBAFactor, RejectsInvalidConstruction)
{
	EXPECT_THROW(PhotometricPatchFactor(some_patch(), nullptr, shipped_dataset_K()), std::invalid_argument);
	EXPECT_THROW(PhotometricPatchFactor(some_patch(), std::make_shared<IntensityImage>(), shipped_dataset_K()),
				 std::invalid_argument);
	auto bad = std::make_shared<IntensityImage>(10, 10);
	bad->pixels.resize(50);
	EXPECT_THROW(PhotometricPatchFactor(some_patch(), bad, shipped_dataset_K()), std::invalid_argument);
}
