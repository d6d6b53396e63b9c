// The synthetic direct-BA room: texture, ray casting, rendering and the perturbed data set (see
// directba_synthetic.h).
#include <swba/core/manifold.h>
#include <swba/factors/photometric_patch.h>
#include <swba/problems/directba_synthetic.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

namespace swba::problems
{
static_assert(kPatchSize == io::kDirectBAPatchSize, "the data set's patches are the photometric factor's");

namespace
{
constexpr double kPi = 3.14159265358979323846;

// The scene: three fronto-parallel planes at different depths, side by side in x (planes 0..2), and
// the two step faces joining them (planes 3, 4; points are never taken on those). Depths 1.8–2.4 m.
constexpr double kStripX[2] = {-0.5, 0.6};          // strip borders in x
constexpr double kStripZ[3] = {2.1, 1.8, 2.4};      // depth of each strip
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

bool synthetic_room_raycast(const mrpt::poses::CPose3D& world_from_camera, const PinholeIntrinsics& K,
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

IntensityImage render_synthetic_room(const mrpt::poses::CPose3D& world_from_camera, const PinholeIntrinsics& K,
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

namespace
{
/** Cameras on an ellipse (0.5 m × 0.3 m) parallel to the planes, small rotations (≤ 0.5°), and the
 * room rendered from each (timestamps = index). */
void add_true_cameras(const SyntheticDirectBAOptions& o, io::DirectBADataset& gt)
{
	const int n = o.num_cameras;
	for (int i = 0; i < n; i++)
	{
		const double s = 2.0 * kPi * double(i) / double(n);
		const Eigen::Vector3d centre(0.5 * std::cos(s), 0.3 * std::sin(s), 0.02 * std::sin(2 * s));
		const Eigen::Matrix3d R = (Eigen::AngleAxisd(deg(-0.5 * std::cos(s)), Eigen::Vector3d::UnitY()) *
								   Eigen::AngleAxisd(deg(0.4 * std::sin(s)), Eigen::Vector3d::UnitX()) *
								   Eigen::AngleAxisd(deg(0.3 * std::cos(3 * s)), Eigen::Vector3d::UnitZ()))
									  .toRotationMatrix();
		gt.world_from_camera.push_back(SE3Manifold::to_pose(R, centre));
		gt.timestamps.push_back(i);
		gt.images.push_back(std::make_shared<IntensityImage>(
			render_synthetic_room(gt.world_from_camera.back(), o.intrinsics, o.width, o.height, o.quantize)));
	}
}

/** Selection of the points at host pixels: which host pixels give a point the photometric model
 * describes exactly at the true values. */
class PointSelection
{
   public:
	PointSelection(const SyntheticDirectBAOptions& o, const io::DirectBADataset& gt)
		: o_(o), gt_(gt), m_(o.plane_margin), edge_(std::max(o.plane_margin, 3) + 2)
	{
	}

	/** Pixels the host-pixel grid starts and stops at the image border. */
	int edge() const { return edge_; }

	/** The point at host pixel (u0, v0) of camera h, if it passes every test below. */
	bool point_at(int h, int u0, int v0, io::DirectBAPoint& pt) const
	{
		Eigen::Vector3d p;
		int plane = -1;
		if (!synthetic_room_raycast(gt_.world_from_camera[h], o_.intrinsics, u0, v0, p, plane)) return false;
		if (plane >= 3 || !on_single_plane(h, u0, v0, plane)) return false;
		if (!seen_consistently(p, plane)) return false;
		pt.position = p;
		return host_patch(*gt_.images[h], u0, v0, pt.patch) >= o_.min_patch_gradient_sq;
	}

   private:
	/** The (2·margin)² neighbourhood of (u, v) in camera `cam` lies on `plane`. */
	bool on_single_plane(int cam, double u, double v, int plane) const
	{
		for (int dv = -m_; dv <= m_; dv += 2)
			for (int du = -m_; du <= m_; du += 2)
			{
				Eigen::Vector3d q;
				int pl = -1;
				if (!synthetic_room_raycast(gt_.world_from_camera[cam], o_.intrinsics, u + du, v + dv, q, pl) ||
					pl != plane)
					return false;
			}
		return true;
	}

	/** Every camera where the point projects into the image must see this very point (not a nearer
	 * plane) with a neighbourhood on the same plane: then "visible wherever it projects inside" holds,
	 * as the photometric factors assume. And it must be well inside at least min_views images. */
	bool seen_consistently(const Eigen::Vector3d& p, int plane) const
	{
		const int n = static_cast<int>(gt_.world_from_camera.size());
		bool consistent = true;
		int views = 0;
		for (int j = 0; j < n && consistent; j++)
		{
			const auto& T = gt_.world_from_camera[j];
			const Eigen::Matrix3d Rj = T.getRotationMatrix().asEigen();
			const Eigen::Vector3d cj(T.x(), T.y(), T.z());
			const Eigen::Vector3d pc = Rj.transpose() * (p - cj);
			const double u = o_.intrinsics.fx * pc.x() / pc.z() + o_.intrinsics.cx;
			const double v = o_.intrinsics.fy * pc.y() / pc.z() + o_.intrinsics.cy;
			if (pc.z() <= 0 || u < -m_ || v < -m_ || u > o_.width - 1 + m_ || v > o_.height - 1 + m_) continue;
			if (u >= edge_ && v >= edge_ && u <= o_.width - 1 - edge_ && v <= o_.height - 1 - edge_) views++;
			Eigen::Vector3d q;
			int pl = -1;
			consistent = synthetic_room_raycast(T, o_.intrinsics, u, v, q, pl) && pl == plane && (q - p).norm() < 1e-6 &&
						 on_single_plane(j, u, v, plane);
		}
		return consistent && views >= std::min(o_.min_views, n);
	}

	/** Fills the 4×4 patch at (u0, v0) and returns the smaller eigenvalue of its structure tensor
	 * (central differences): both eigenvalues large means the patch is textured in every direction
	 * (no aperture problem along epipolar lines). */
	static double host_patch(const IntensityImage& img, int u0, int v0, io::DirectBAPatch& patch)
	{
		double sxx = 0, sxy = 0, syy = 0;
		for (int k = 0; k < kPatchSize; k++)
		{
			const int x = u0 + patch_offset_x(k), y = v0 + patch_offset_y(k);
			patch[k] = img.at(x, y);
			const double gx = 0.5 * (img.at(x + 1, y) - img.at(x - 1, y));
			const double gy = 0.5 * (img.at(x, y + 1) - img.at(x, y - 1));
			sxx += gx * gx;
			sxy += gx * gy;
			syy += gy * gy;
		}
		sxx /= kPatchSize;
		sxy /= kPatchSize;
		syy /= kPatchSize;
		return 0.5 * (sxx + syy) - std::sqrt(0.25 * (sxx - syy) * (sxx - syy) + sxy * sxy);
	}

	const SyntheticDirectBAOptions& o_;
	const io::DirectBADataset& gt_;
	const int m_;     ///< plane margin
	const int edge_;  ///< host pixels are at least this far from the border
};

/** Perturbed start: poses ⊞ δ for the free cameras (index ≥ fixed_cameras), points + noise. */
void perturb(const SyntheticDirectBAOptions& o, io::DirectBADataset& initial)
{
	std::mt19937 rng(o.seed);
	std::normal_distribution<double> n01(0.0, 1.0);
	const SE3Manifold se3;
	for (int i = o.fixed_cameras; i < o.num_cameras; i++)
	{
		double x[12], delta[6];
		SE3Manifold::from_pose(initial.world_from_camera[i], x);
		for (int k = 0; k < 3; k++) delta[k] = o.pose_translation_sigma_m * n01(rng);
		for (int k = 3; k < 6; k++) delta[k] = deg(o.pose_rotation_sigma_deg) * n01(rng);
		se3.plus(x, delta, x);
		initial.world_from_camera[i] = SE3Manifold::to_pose(x);
	}
	for (auto& pt : initial.points)
		for (int k = 0; k < 3; k++) pt.position[k] += o.point_sigma_m * n01(rng);
}
}  // namespace

SyntheticDirectBA make_synthetic_directba(const SyntheticDirectBAOptions& o)
{
	if (o.num_cameras < 2) throw std::invalid_argument("synthetic directba: num_cameras must be ≥ 2");
	if (o.width < 32 || o.height < 32) throw std::invalid_argument("synthetic directba: image too small");
	if (o.min_views < 1 || o.point_grid_step < 1 || o.plane_margin < 0 || o.fixed_cameras < 0)
		throw std::invalid_argument("synthetic directba: invalid grid step, margin or fixed camera count");

	SyntheticDirectBA out;
	io::DirectBADataset& gt = out.truth;
	gt.intrinsics = o.intrinsics;
	add_true_cameras(o, gt);
	// Points at host pixels of the first and the last camera.
	const PointSelection selection(o, gt);
	const int edge = selection.edge();
	for (int h : {0, o.num_cameras - 1})
		for (int v0 = edge; v0 < o.height - edge; v0 += o.point_grid_step)
			for (int u0 = edge; u0 < o.width - edge; u0 += o.point_grid_step)
			{
				io::DirectBAPoint pt;
				if (!selection.point_at(h, u0, v0, pt)) continue;
				gt.points.push_back(pt);
				out.host_camera.push_back(h);
			}
	out.initial = gt;
	perturb(o, out.initial);
	return out;
}
}  // namespace swba::problems
