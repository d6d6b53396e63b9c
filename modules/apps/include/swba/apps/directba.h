/** \file directba.h
 * `swba directba`: direct (photometric) bundle adjustment over a swba::io::DirectBADataset: one
 * PhotometricPatchFactor per (point, camera) pair, points eliminated by Schur (Group::Eliminable),
 * the first `fixed_cameras` poses held constant (gauge), solved by swba::solve.
 * Also the synthetic check: the same adjustment on problems::make_synthetic_directba() with errors
 * against ground truth. See doc/directba.md. */
#pragma once

#include <swba/factors/photometric_patch.h>
#include <swba/io/directba_dataset.h>
#include <swba/nonlinear/solver.h>
#include <swba/problems/directba_synthetic.h>

#include <cmath>
#include <iosfwd>
#include <stdexcept>
#include <string>
#include <vector>

namespace swba::apps
{
struct DirectBAOptions
{
	/** LM options; progress_to_stdout prints the iteration table. Default max_iterations 50. */
	SolverOptions solver;
	/** Photometric noise σ in gray levels: residuals are whitened by 1/σ. Default 10. */
	double sigma = 10.0;
	/** Huber threshold in whitened units (applied to ‖r/σ‖); ≤ 0 disables the robust kernel.
	 * Default √χ²₁₆(0.95) = √26.296 ≈ 5.128, i.e. a patch residual norm of 5.128·σ. */
	double huber_delta = std::sqrt(kChi2Patch95);
	/** The first `fixed_cameras` poses are constant (gauge). Default 1. */
	int fixed_cameras = 1;
	/** Factor options (image border margin, minimum depth). */
	PhotometricPatchFactor::Options factor;

	/** Throws std::invalid_argument naming the option that is out of range. */
	void validate() const;
};

/** Photometric statistics at one set of values. */
struct DirectBAStats
{
	double cost = 0;        ///< ½Σρ(‖r/σ‖²) over the evaluable factors (as the solver's cost)
	int evaluated = 0;      ///< factors with a defined residual
	int dropped = 0;        ///< factors whose patch left the image or whose point was behind
	double pixel_rms = 0;   ///< √(Σ r_k² / (16·evaluated)), gray levels, no robust kernel
	double pixel_median_abs = 0;  ///< median |r_k| over all evaluated samples, gray levels
};

/** How far the adjustment moved the variables (final vs initial). */
struct DirectBAMotion
{
	double pose_translation_max = 0, pose_translation_rms = 0;  ///< camera centres (data units)
	double pose_rotation_max_deg = 0, pose_rotation_rms_deg = 0;
	double point_mean = 0, point_median = 0, point_max = 0;     ///< point displacements
};

struct DirectBAResult
{
	Summary summary;
	DirectBAStats before, after;
	DirectBAMotion motion;
	int num_factors = 0;
	std::vector<mrpt::poses::CPose3D> poses;  ///< optimised world-from-camera poses
	std::vector<Eigen::Vector3d> points;      ///< optimised points
};

/** Thrown by run_direct_ba when options.fixed_cameras exceeds the data set's number of cameras: valid
 * options that do not fit this input (`swba directba` reports a bad --fixed-cameras). */
struct DirectBAFixedCamerasError : std::invalid_argument
{
	DirectBAFixedCamerasError(int fixed_cameras, int num_cameras);
	int fixed_cameras;  ///< requested
	int num_cameras;    ///< in the data set
};

/** Builds and solves the problem. Throws std::invalid_argument on invalid options or a data set
 * whose images do not match its poses (DirectBAFixedCamerasError: more fixed cameras than it has). */
DirectBAResult run_direct_ba(const io::DirectBADataset& data, const DirectBAOptions& options);

/** Statistics of the photometric factors at the given values (used before/after the solve). */
DirectBAStats direct_ba_stats(const io::DirectBADataset& data, const std::vector<mrpt::poses::CPose3D>& poses,
							  const std::vector<Eigen::Vector3d>& points, const DirectBAOptions& options);

/** Errors of poses/points against ground truth. */
struct DirectBAGroundTruthErrors
{
	double pose_translation_max_m = 0, pose_rotation_max_deg = 0;
	double point_rms_m = 0, point_max_m = 0;
	/** Displacement of the projections (all in-image point×camera pairs) vs ground truth, pixels. */
	double reprojection_mean_px = 0, reprojection_max_px = 0;
};
DirectBAGroundTruthErrors direct_ba_ground_truth_errors(const io::DirectBADataset& truth,
														const std::vector<mrpt::poses::CPose3D>& poses,
														const std::vector<Eigen::Vector3d>& points);

struct SyntheticDirectBAResult
{
	DirectBAResult result;
	DirectBAGroundTruthErrors initial_errors, final_errors;
	int num_points = 0, num_cameras = 0;
};

/** Renders the synthetic room, perturbs it and runs run_direct_ba(); the options' fixed_cameras is
 * set to the scene's (cameras left at ground truth). */
SyntheticDirectBAResult run_synthetic_direct_ba(const problems::SyntheticDirectBAOptions& scene,
												DirectBAOptions options);

/** Human-readable report lines (cost, RMS, dropped, motion). */
std::string format_direct_ba_report(const DirectBAResult& r);
std::string format_direct_ba_ground_truth_errors(const DirectBAGroundTruthErrors& before,
												const DirectBAGroundTruthErrors& after);

/** Options of `swba directba`: the data set (or the synthetic room), the adjustment, the outputs. */
struct DirectBAAppOptions
{
	/** Data set directory (poses.txt, points.txt, 0.png … N−1.png); empty with `synthetic`. */
	std::string dataset_dir;
	/** Run the synthetic check instead: render `scene`, perturb, adjust, compare with ground truth. */
	bool synthetic = false;
	/** The synthetic room; its fixed_cameras (default 2) replaces adjustment.fixed_cameras. */
	problems::SyntheticDirectBAOptions scene;
	/** The adjustment (σ, Huber threshold, fixed cameras: default 1, border, LM options). */
	DirectBAOptions adjustment;
	/** Data set only: PLY of the initial / optimised cameras and points (empty: not written). */
	std::string ply_initial, ply_final;
	/** Data set only: directory for poses_initial.tum, poses_final.tum and points_final.ply, created
	 * (empty: not written). */
	std::string out_dir;

	/** Throws std::invalid_argument on invalid adjustment options, a directory with `synthetic` or none
	 * without. */
	void validate() const;
};

struct DirectBAAppResult
{
	DirectBAResult result;
	/** Synthetic check: poses within 1 mm / 0.05° and every point within 1 cm of the ground truth. */
	bool synthetic_pass = false;
};

/** Runs the adjustment on the data set (or the synthetic check) and prints the report to `out`, the "Wrote <file>" lines to `log`.
 * Throws std::invalid_argument on invalid options, std::runtime_error on unreadable data,
 * unwritable outputs or a failed optimisation of the data set (after the report). */
DirectBAAppResult run_directba_app(const DirectBAAppOptions& options, std::ostream& out, std::ostream& log);
}  // namespace swba::apps
