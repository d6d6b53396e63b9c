/** \file photometric_patch.h
 * Direct (photometric) bundle adjustment: a 4×4 intensity patch of a 3-D point, taken from its host
 * image, compared with a target image sampled by bilinear interpolation around the point's
 * projection (the residual of the directBA.cpp that came with the shipped data set, share/data/directba/
 * PROVENANCE.txt, with analytic Jacobians).
 *
 * Conventions (see doc/directba.md for the derivation):
 * - The pose variable stores **world-from-camera** T_wc = [R | t] (SE3Manifold, right perturbation
 *   T ⊞ δ = T·PseudoExp(δ), δ = [ρ, ω]); a world point p_w is seen at p_c = Rᵀ(p_w − t).
 * - Pixel (i, j) of an image has its centre at u = i, v = j; u = fx·x/z + cx, v = fy·y/z + cy.
 * - Patch sample k = 4·(dx + 2) + (dy + 2) for dx, dy ∈ {−2, −1, 0, 1} (dx outer, as in that directBA.cpp).
 */
#pragma once

#include <swba/core/factor.h>
#include <swba/core/image.h>

#include <Eigen/Core>
#include <array>
#include <memory>

namespace swba
{
/** Result of bilinear sampling: the interpolated value and the gradient of the bilinear
 * interpolant (exact derivative inside a pixel cell; one-sided at cell borders). */
struct BilinearSample
{
	double value = 0;
	double du = 0;  ///< ∂I/∂u
	double dv = 0;  ///< ∂I/∂v
};

/** True when bilinear sampling at (u, v) reads only pixels inside the image:
 * 0 ≤ u, 0 ≤ v, ⌊u⌋+1 ≤ width−1, ⌊v⌋+1 ≤ height−1 (and u, v finite). */
bool bilinear_in_bounds(const IntensityImage& image, double u, double v);

/** Bilinear interpolation of `image` at (u, v) with its gradient. Returns false (and leaves `out`
 * untouched) when the four neighbours are not all inside the image — never reads out of bounds. */
bool sample_bilinear(const IntensityImage& image, double u, double v, BilinearSample& out);

/** Pinhole intrinsics of the target images (swba/core/image.h). */
using PatchCameraIntrinsics = PinholeIntrinsics;

/** Size of the patch: 4×4 samples at offsets −2..1 in x and y. */
constexpr int kPatchSize = 16;
using PatchValues = std::array<double, kPatchSize>;
/** Offset of patch sample k: dx = k / 4 − 2, dy = k % 4 − 2. */
inline int patch_offset_x(int k) { return k / 4 - 2; }
inline int patch_offset_y(int k) { return k % 4 - 2; }

/** χ²(16 DoF) 95 % quantile: the squared whitened residual norm below which a patch counts as an
 * inlier; the default Huber threshold is its square root (≈ 5.128, in whitened units). */
constexpr double kChi2Patch95 = 26.296;

/**
 * r_k = host_patch_k − I_target(u + dx_k, v + dy_k), k = 0..15, (u, v) = π(T_wc⁻¹ p_w).
 * Variables: [0] the target camera's pose T_wc (SE3Manifold), [1] the point p_w (R³).
 * Jacobians: ∂r_k/∂(u,v) = −∇I (gradient of the bilinear interpolant at the sample) times the
 * projection Jacobian: ∂p_c/∂ρ = −I, ∂p_c/∂ω = [p_c]×, ∂p_c/∂p_w = Rᵀ.
 * evaluate() returns false (residual dropped for that evaluation) when the point is not in front of
 * the camera (z ≤ min_depth) or when any patch sample lies closer than `border` pixels to the
 * image edge (bilinear neighbours included); it never reads outside the image buffer.
 */
class PhotometricPatchFactor final : public Factor
{
   public:
	struct Options
	{
		/** Extra margin (pixels) kept between the bilinear footprint of the patch and the image
		 * edge. Default 1. */
		int border = 1;
		/** Points with camera-frame depth z ≤ min_depth (same unit as the poses) are dropped.
		 * Default 1e-6. */
		double min_depth = 1e-6;
	};

	PhotometricPatchFactor(const PatchValues& host_patch, std::shared_ptr<const IntensityImage> target,
						   const PatchCameraIntrinsics& intrinsics, const Options& options);
	PhotometricPatchFactor(const PatchValues& host_patch, std::shared_ptr<const IntensityImage> target,
						   const PatchCameraIntrinsics& intrinsics)
		: PhotometricPatchFactor(host_patch, std::move(target), intrinsics, Options())
	{
	}

	bool evaluate(const double* const* x, double* residual, double* const* jacobians) const override;

	/** Projection (u, v) of p_w into the camera T_wc; false if z ≤ min_depth. */
	bool project(const double* pose_wc, const double* point_w, double& u, double& v) const;
	/** True if the whole patch around (u, v), with its bilinear footprint and the border, is inside. */
	bool patch_inside(double u, double v) const;

	const PatchValues& host_patch() const { return host_patch_; }
	const IntensityImage& target() const { return *target_; }

   private:
	PatchValues host_patch_;
	std::shared_ptr<const IntensityImage> target_;
	PatchCameraIntrinsics K_;
	Options opt_;
};
}  // namespace swba
