/** \file alignment.h
 * Aligning an estimated trajectory to a reference: Umeyama SE(3) / Sim(3) / scale only (Eigen::umeyama),
 * or origin alignment — the same steps, in the same order, as evo_ape's `-a`, `-s`, `--align_origin`. */
#pragma once

#include <Eigen/Core>
#include <string>

#include "swba/eval/trajectory.h"

namespace swba::eval
{
/** x ↦ scale · R · x + t. */
struct Sim3
{
	Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
	Eigen::Vector3d t = Eigen::Vector3d::Zero();
	double scale = 1.0;
	/** The 4×4 matrix [scale·R t; 0 1]. */
	Eigen::Matrix4d matrix() const;
};

/** Least-squares Sim(3) (with_scale) or SE(3) mapping src columns onto dst columns (Umeyama 1991,
 * via Eigen::umeyama; a reflection is never returned: det R = +1). src and dst are 3×N.
 * Throws std::invalid_argument on size mismatch, N = 0, a cross-covariance of rank < 2 (evo's
 * "Degenerate covariance rank, Umeyama alignment is not possible": 1 or 2 points, or collinear ones;
 * evo raises there too instead of returning a transform the data do not determine; it covers src
 * points all equal, where no scale could be estimated either). */
Sim3 umeyama_alignment(const Eigen::Matrix3Xd& src, const Eigen::Matrix3Xd& dst, bool with_scale);

/** Least-squares rigid motion restricted to a rotation about z and a translation (the four-DoF gauge of
 * visual-inertial and IMU + odometry estimates, gravity along z) mapping src columns onto dst columns:
 * Umeyama's solution with the rotation confined to the xy plane, yaw = atan2(Σ (s × d)_z, Σ s_xy · d_xy)
 * over the centred points. Throws std::invalid_argument on size mismatch, N = 0 or centred points whose
 * xy parts do not determine the yaw (all on the z axis). */
Sim3 yaw_alignment(const Eigen::Matrix3Xd& src, const Eigen::Matrix3Xd& dst);

/** Alignment flags, as evo: align = `-a`, correct_scale = `-s`, align_origin = `--align-origin`.
 *  - align only: SE(3) Umeyama;      - align + correct_scale: Sim(3) Umeyama;
 *  - correct_scale only: the Sim(3) Umeyama scale applied to positions, no rotation/translation;
 *  - align_origin (after any of the above): est ← ref₀ · est₀⁻¹ · est. */
struct AlignmentOptions
{
	bool align = false;
	bool correct_scale = false;
	bool align_origin = false;
	bool any() const { return align || correct_scale || align_origin; }
};

/** What align_trajectory() applied. `transform` is the Umeyama result (identity if not run);
 * `origin` the origin alignment (identity if not run). est_after = origin ∘ transform(est_before),
 * where Sim(3) scales the translations of est poses and then left-multiplies by [R t]. */
struct AlignmentResult
{
	Sim3 transform;
	Eigen::Matrix4d origin = Eigen::Matrix4d::Identity();
};

/** Aligns `est` in place to `ref` (both associated: same length, pose i ↔ pose i). */
AlignmentResult align_trajectory(Trajectory& est, const Trajectory& ref, const AlignmentOptions& options);

/** evo's title suffix, e.g. "(not aligned)", "(with SE(3) Umeyama alignment)",
 * "(with Sim(3) Umeyama alignment)", "(scale corrected)", "(with origin alignment)", lines joined by '\n'. */
std::string alignment_title(const AlignmentOptions& options);

/** 4×4 homogeneous matrix of a pose, and back (the rotation block must be orthonormal). */
Eigen::Matrix4d to_matrix(const mrpt::poses::CPose3D& pose);
mrpt::poses::CPose3D from_matrix(const Eigen::Matrix4d& T);
}  // namespace swba::eval
