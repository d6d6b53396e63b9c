/** \file monoba.h
 * The synthetic scene of monocular bundle adjustment (`swba monoba`, doc/monoba.md).
 *
 * Scene: N cameras on a circular arc of radius r looking along +z (camera n at angle
 * θ_n = n·(π/2)/N about the world z axis, t_n = (r cos θ_n − r, r sin θ_n, sin 2θ_n)), M points
 * uniform in [−4, 4] × [−4, 4] × [4, 8] m. Camera poses are T_wc (camera-to-world, SE3Manifold).
 * Each point is an inverse depth λ in its first observing camera (the host); its host bearing is the
 * noisy first observation. Observations are on the normalised image plane with Gaussian noise σ (per
 * coordinate). The problem built from a scene (gauge handling included) is in swba/apps/monoba.h. */
#pragma once

#include <mrpt/poses/CPose3D.h>

#include <Eigen/Core>
#include <string>
#include <vector>

namespace swba::problems
{
struct MonoBASceneOptions
{
	/** Number of cameras N (≥ 2). Default 3. */
	int cameras = 3;
	/** Number of points M (≥ 1). Default 20. */
	int points = 20;
	/** Radius of the camera arc, m. Default 8. */
	double arc_radius_m = 8.0;
	/** σ of the observation noise on the normalised image plane (≥ 0). Default 1/460 (one pixel
	 * at a focal length of 460 px, EuRoC-like). Factors are whitened by 1/σ (by 460 when σ = 0). */
	double noise = 1.0 / 460.0;
	/** σ of the perturbation of the initial depths, m: λ₀ = 1/(z + n), n ~ N(0, σ²), redrawn while
	 * z + n < 0.5 m. Default 1. */
	double depth_noise_m = 1.0;
	/** Initial pose perturbation of the cameras with index ≥ `pose_noise_from` (right perturbation,
	 * translation σ in m, rotation σ in rad per axis). Default 0 (poses start at ground truth). */
	double pose_noise_m = 0.0;
	double pose_noise_rad = 0.0;
	/** First camera index that receives pose noise (the anchors before it start at ground truth). Default 2. */
	int pose_noise_from = 2;
	/** RNG seed (std::mt19937). Default 0. */
	unsigned seed = 0;

	/** Throws std::invalid_argument naming the option that is out of range. */
	void validate() const;
};

struct MonoBAObservation
{
	int camera = 0;
	Eigen::Vector2d uv;  ///< noisy observation on the normalised image plane
};

struct MonoBAPoint
{
	Eigen::Vector3d world;          ///< ground-truth position, m
	int host = 0;                   ///< first observing camera
	Eigen::Vector2d host_bearing;   ///< the host's noisy observation (fixed bearing [u, v, 1])
	double true_inverse_depth = 0;  ///< 1 / z of the true point in the host frame
	double initial_inverse_depth = 0;
	std::vector<MonoBAObservation> observations;  ///< by the other cameras (one factor each)
};

struct MonoBAScene
{
	MonoBASceneOptions options;
	std::vector<mrpt::poses::CPose3D> true_poses;     ///< T_wc
	std::vector<mrpt::poses::CPose3D> initial_poses;  ///< T_wc
	std::vector<MonoBAPoint> points;
};

/** Generates the scene; deterministic for a given seed. Points seen by fewer than two cameras
 * (z ≤ 0.1 m in the camera) are redrawn. Throws std::invalid_argument on invalid options. */
MonoBAScene make_monoba_scene(const MonoBASceneOptions& options);
}  // namespace swba::problems
