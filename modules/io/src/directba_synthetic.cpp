#include <swba/core/manifold.h>
#include <swba/io/directba_synthetic.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

namespace swba::io
{
namespace
{
constexpr double kPi = 3.14159265358979323846;

// The scene: three fronto-parallel planes at different depths, side by side in x (planes 0..2), and
// the two step faces joining them (planes 3, 4; points are never taken on those). Depths 1.8–2.4 m.
constexpr double kStripX[2] = {-0.5, 0.6};          // strip borders in x
constexpr double kStripZ[3] = {2.1, 1.8, 2.4};      // depth of each strip
constexpr int kNumScenePlanes = 5;
mrpt::poses::CPose3D make_pose(const Eigen::Matrix3d& R, const Eigen::Vector3d& t)
{
	mrpt::math::CMatrixDouble33 M;
	M.asEigen() = R;
	return mrpt::poses::CPose3D(M, mrpt::math::CVectorFixedDouble<3>({t.x(), t.y(), t.z()}));
}

double deg(double d) { return d * kPi / 180.0; }
}  // namespace

double synthetic_room_texture(int plane, const Eigen::Vector3d& p)
{
	// A sum of sinusoids with wavelengths 0.22 .. 0.55 m (≈ 30–80 px at 2 m) in four directions, of
	// (x, y) on the strips and of (z, y) on the step faces: smooth at the pixel scale and textured in
	// every direction.
	static constexpr double amp[4] = {30, 25, 20, 15};
	static constexpr double wavelength[4] = {0.225, 0.3, 0.4, 0.55};
	static constexpr double angle_deg[4] = {10, 70, 130, 200};
	static constexpr double phase[4] = {0.0, 1.3, 2.6, 3.9};
	const double a = plane < 3 ? p.x() : p.z();
	double I = 128.0;
	for (int j = 0; j < 4; j++)
	{
		const double th = deg(angle_deg[j]);
		I += amp[j] * std::sin(2.0 * kPi * (std::cos(th) * a + std::sin(th) * p.y()) / wavelength[j] + phase[j]);
	}
	return I;
}

bool synthetic_room_raycast(const mrpt::poses::CPose3D& world_from_camera, const PatchCameraIntrinsics& K,
							double u, double v, Eigen::Vector3d& hit, int& plane)
{
	const Eigen::Matrix3d R = world_from_camera.getRotationMatrix().asEigen();
	const Eigen::Vector3d c(world_from_camera.x(), world_from_camera.y(), world_from_camera.z());
	const Eigen::Vector3d d = R * Eigen::Vector3d((u - K.cx) / K.fx, (v - K.cy) / K.fy, 1.0);
	double best = std::numeric_limits<double>::infinity();
	plane = -1;
	auto consider = [&](double lambda, int id) {
		if (lambda > 0 && lambda < best)
		{
			best = lambda;
			plane = id;
		}
	};
	auto strip_of = [&](double x) { return x < kStripX[0] ? 0 : (x < kStripX[1] ? 1 : 2); };
	if (d.z() > 1e-12)
		for (int i = 0; i < 3; i++)
		{
			const double lambda = (kStripZ[i] - c.z()) / d.z();
			if (strip_of(c.x() + lambda * d.x()) == i) consider(lambda, i);
		}
	if (std::abs(d.x()) > 1e-12)
		for (int k = 0; k < 2; k++)
		{
			const double lambda = (kStripX[k] - c.x()) / d.x();
			const double z = c.z() + lambda * d.z();
			if (z >= std::min(kStripZ[k], kStripZ[k + 1]) && z <= std::max(kStripZ[k], kStripZ[k + 1]))
				consider(lambda, 3 + k);
		}
	if (plane < 0) return false;
	hit = c + best * d;
	return true;
}

IntensityImage render_synthetic_room(const mrpt::poses::CPose3D& world_from_camera, const PatchCameraIntrinsics& K,
									 int width, int height, bool quantize)
{
	IntensityImage img(width, height);
	for (int r = 0; r < height; r++)
		for (int c = 0; c < width; c++)
		{
			Eigen::Vector3d p;
			int plane = -1;
			double I = 0.0;
			if (synthetic_room_raycast(world_from_camera, K, c, r, p, plane)) I = synthetic_room_texture(plane, p);
			img.at(c, r) = static_cast<float>(quantize ? std::round(I) : I);
		}
	return img;
}

SyntheticDirectBA make_synthetic_directba(const SyntheticDirectBAOptions& o)
{
	if (o.num_cameras < 2) throw std::invalid_argument("synthetic directba: num_cameras must be ≥ 2");
	if (o.width < 32 || o.height < 32) throw std::invalid_argument("synthetic directba: image too small");
	if (o.min_views < 1 || o.point_grid_step < 1 || o.plane_margin < 0 || o.fixed_cameras < 0)
		throw std::invalid_argument("synthetic directba: invalid grid step, margin or fixed camera count");

	SyntheticDirectBA out;
	DirectBADataset& gt = out.truth;
	gt.intrinsics = o.intrinsics;
	const int n = o.num_cameras;
	for (int i = 0; i < n; i++)
	{
		// On an ellipse (0.5 m × 0.3 m) parallel to the planes, small rotations (≤ 0.5°).
		const double s = 2.0 * kPi * double(i) / double(n);
		const Eigen::Vector3d centre(0.5 * std::cos(s), 0.3 * std::sin(s), 0.02 * std::sin(2 * s));
		const Eigen::Matrix3d R = (Eigen::AngleAxisd(deg(-0.5 * std::cos(s)), Eigen::Vector3d::UnitY()) *
								   Eigen::AngleAxisd(deg(0.4 * std::sin(s)), Eigen::Vector3d::UnitX()) *
								   Eigen::AngleAxisd(deg(0.3 * std::cos(3 * s)), Eigen::Vector3d::UnitZ()))
									  .toRotationMatrix();
		gt.world_from_camera.push_back(make_pose(R, centre));
		gt.timestamps.push_back(i);
		gt.images.push_back(std::make_shared<IntensityImage>(
			render_synthetic_room(gt.world_from_camera.back(), o.intrinsics, o.width, o.height, o.quantize)));
	}

	// Points at host pixels of the first and the last camera.
	const int hosts[2] = {0, n - 1};
	const int m = o.plane_margin;
	const int edge = std::max(m, 3) + 2;
	auto on_single_plane = [&](int cam, double u, double v, int plane) {
		for (int dv = -m; dv <= m; dv += 2)
			for (int du = -m; du <= m; du += 2)
			{
				Eigen::Vector3d q;
				int pl = -1;
				if (!synthetic_room_raycast(gt.world_from_camera[cam], o.intrinsics, u + du, v + dv, q, pl) ||
					pl != plane)
					return false;
			}
		return true;
	};
	for (int h : hosts)
	{
		const IntensityImage& img = *gt.images[h];
		for (int v0 = edge; v0 < o.height - edge; v0 += o.point_grid_step)
			for (int u0 = edge; u0 < o.width - edge; u0 += o.point_grid_step)
			{
				Eigen::Vector3d p;
				int plane = -1;
				if (!synthetic_room_raycast(gt.world_from_camera[h], o.intrinsics, u0, v0, p, plane)) continue;
				if (plane >= 3 || !on_single_plane(h, u0, v0, plane)) continue;
				// Every camera where the point projects into the image must see this very point (not
				// a nearer plane) with a neighbourhood on the same plane: then "visible wherever it
				// projects inside" holds, as the photometric factors assume.
				bool consistent = true;
				int views = 0;
				for (int j = 0; j < n && consistent; j++)
				{
					const Eigen::Matrix3d Rj = gt.world_from_camera[j].getRotationMatrix().asEigen();
					const Eigen::Vector3d cj(gt.world_from_camera[j].x(), gt.world_from_camera[j].y(),
											 gt.world_from_camera[j].z());
					const Eigen::Vector3d pc = Rj.transpose() * (p - cj);
					const double u = o.intrinsics.fx * pc.x() / pc.z() + o.intrinsics.cx;
					const double v = o.intrinsics.fy * pc.y() / pc.z() + o.intrinsics.cy;
					if (pc.z() <= 0 || u < -m || v < -m || u > o.width - 1 + m || v > o.height - 1 + m) continue;
					if (u >= edge && v >= edge && u <= o.width - 1 - edge && v <= o.height - 1 - edge) views++;
					Eigen::Vector3d q;
					int pl = -1;
					consistent = synthetic_room_raycast(gt.world_from_camera[j], o.intrinsics, u, v, q, pl) &&
								 pl == plane && (q - p).norm() < 1e-6 && on_single_plane(j, u, v, plane);
				}
				if (!consistent || views < std::min(o.min_views, n)) continue;
				DirectBAPoint pt;
				pt.position = p;
				// Structure tensor of the patch (central differences): both eigenvalues large means
				// the patch is textured in every direction (no aperture problem along epipolar lines).
				double sxx = 0, sxy = 0, syy = 0;
				for (int k = 0; k < kPatchSize; k++)
				{
					const int x = u0 + patch_offset_x(k), y = v0 + patch_offset_y(k);
					pt.patch[k] = img.at(x, y);
					const double gx = 0.5 * (img.at(x + 1, y) - img.at(x - 1, y));
					const double gy = 0.5 * (img.at(x, y + 1) - img.at(x, y - 1));
					sxx += gx * gx;
					sxy += gx * gy;
					syy += gy * gy;
				}
				sxx /= kPatchSize;
				sxy /= kPatchSize;
				syy /= kPatchSize;
				const double min_eig = 0.5 * (sxx + syy) - std::sqrt(0.25 * (sxx - syy) * (sxx - syy) + sxy * sxy);
				if (min_eig < o.min_patch_gradient_sq) continue;
				gt.points.push_back(pt);
				out.host_camera.push_back(h);
			}
	}

	// Perturbed start: same images, poses ⊞ δ for the free cameras, points + noise.
	out.initial = gt;
	std::mt19937 rng(o.seed);
	std::normal_distribution<double> n01(0.0, 1.0);
	const SE3Manifold se3;
	for (int i = o.fixed_cameras; i < n; i++)
	{
		double x[12], delta[6];
		SE3Manifold::from_pose(gt.world_from_camera[i], x);
		for (int k = 0; k < 3; k++) delta[k] = o.pose_translation_sigma_m * n01(rng);
		for (int k = 3; k < 6; k++) delta[k] = deg(o.pose_rotation_sigma_deg) * n01(rng);
		se3.plus(x, delta, x);
		out.initial.world_from_camera[i] = SE3Manifold::to_pose(x);
	}
	for (auto& pt : out.initial.points)
		for (int k = 0; k < 3; k++) pt.position[k] += o.point_sigma_m * n01(rng);
	return out;
}
}  // namespace swba::io
