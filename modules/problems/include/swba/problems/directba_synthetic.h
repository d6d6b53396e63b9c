/** \file directba_synthetic.h
 * A synthetic direct-BA data set with ground truth: the inside of a box-shaped room (5 planes with a
 * smooth procedural texture) rendered by ray casting from known camera poses, points taken at host
 * pixels with their 4×4 patches, then poses and points perturbed. Everything stays in memory.
 *
 * Scene (metres; world frame: x right, y down, z forward — the cameras look along +z): three
 * fronto-parallel textured planes side by side, z = 2.1 m for x < −0.5, z = 1.8 m for −0.5 ≤ x < 0.6,
 * z = 2.4 m for x ≥ 0.6, joined by two step faces. Six cameras on a 1.0 m × 0.6 m ellipse in the
 * plane z ≈ 0 (±2 cm), rotated by ≤ 0.5°. Points are kept only where the host patch and its
 * surroundings lie on one plane and the point is seen un-occluded, well inside every image. */
#pragma once

#include <swba/io/directba_dataset.h>

#include <cstdint>

namespace swba::problems
{
struct SyntheticDirectBAOptions
{
	int width = 640, height = 480;
	/** Intrinsics: those of the shipped data set (fx=277.34 fy=291.402 cx=312.234 cy=239.777) by default. */
	PinholeIntrinsics intrinsics = io::directba_dataset_intrinsics();
	/** Number of cameras (≥ 2). Default 6. */
	int num_cameras = 6;
	/** Host-pixel grid step (pixels) in each host image; hosts are the first and the last camera.
	 * Default 10 (≈ 650 points pass the selection below). */
	int point_grid_step = 10;
	/** Host pixels whose (2·plane_margin)² neighbourhood is not on a single plane are skipped
	 * (a patch straddling two walls breaks the model). Default 6 px. */
	int plane_margin = 6;
	/** Host patches whose structure tensor (mean of ∇I∇Iᵀ over the 16 samples, central differences)
	 * has its smaller eigenvalue below this (gray²/px²) are skipped (aperture problem). Default 1. */
	double min_patch_gradient_sq = 1.0;
	/** Points must be well inside (patch + plane_margin) this many images at the true values, so that
	 * their depth is well constrained. Default 6 (all cameras). */
	int min_views = 6;
	/** Round rendered intensities to integers, like an 8-bit image. Default false (float images:
	 * with rounding a few points converge to a neighbouring minimum, see doc/directba.md). */
	bool quantize = false;
	/** Perturbation of the free cameras (those with index ≥ fixed_cameras): per-axis Gaussian
	 * translation σ (m) and rotation σ (deg). Defaults 0.01 m, 0.2°. */
	double pose_translation_sigma_m = 0.01;
	double pose_rotation_sigma_deg = 0.2;
	/** Cameras left at ground truth (the gauge the optimiser fixes). Default 2. */
	int fixed_cameras = 2;
	/** Per-axis Gaussian perturbation of every point (m). Default 0.01 m. */
	double point_sigma_m = 0.01;
	/** Seed of the perturbation RNG (std::mt19937). Default 7. */
	uint32_t seed = 7;
};

struct SyntheticDirectBA
{
	/** Ground-truth poses and points; images rendered at the true poses (timestamps = index). */
	io::DirectBADataset truth;
	/** Same images, perturbed poses (cameras ≥ fixed_cameras) and points: the optimiser's start. */
	io::DirectBADataset initial;
	/** Host camera of each point. */
	std::vector<int> host_camera;
};

/** Texture intensity of the room at a world point on one of its planes (plane id 0..4). */
double synthetic_room_texture(int plane, const Eigen::Vector3d& p);

/** Casts the ray of pixel (u, v) of camera T_wc into the room; returns the hit point and plane id.
 * False if the ray misses (cannot happen for a camera inside the room). */
bool synthetic_room_raycast(const mrpt::poses::CPose3D& world_from_camera, const PinholeIntrinsics& K,
							double u, double v, Eigen::Vector3d& hit, int& plane);

/** Renders the room from T_wc (pixel centres at integer coordinates). */
IntensityImage render_synthetic_room(const mrpt::poses::CPose3D& world_from_camera, const PinholeIntrinsics& K,
									 int width, int height, bool quantize);

/** Builds the synthetic data set; throws std::invalid_argument on invalid options. Deterministic. */
SyntheticDirectBA make_synthetic_directba(const SyntheticDirectBAOptions& options = {});
}  // namespace swba::problems
