/** \file nees.h
 * Normalised estimation error squared (NEES) of an estimate against the ground truth, from the
 * covariance files `swba run` writes next to its TUM files (doc/sweeps.md, "Covariance files"), and
 * its average over N independent runs with the two-sided χ² band.
 *
 * No alignment: under the fixed gauge the estimate's frame is the frame of its first pose, so the
 * ground truth is expressed relative to its own row 0 (T₀⁻¹·T_k) before the comparison — an identity
 * for MRPT's simulated paths, which start at the origin. Aligning would remove part of the very error
 * whose covariance is being tested.
 *
 * Tangent convention of the 6×6 pose covariance (swba's SE3Manifold, mrpt::poses::Lie::SE<3>): right
 * perturbation T_true = T_est·Exp(δ), δ = [ρ, ω], t ← t + R·ρ, R ← R·Exp(ω); so ρ = R_estᵀ(t_true −
 * t_est) and ω = Log(R_estᵀ·R_true). Position NEES uses the world-frame error e = t_true − t_est with
 * the 3×3 position covariance.
 *
 * Degenerate degrees of freedom: a dof whose row and column of the covariance are zero (a planar
 * estimator's z, roll, pitch) is fixed, not estimated; it is left out and the NEES has that many fewer
 * dof (NeesValue::dof says how many were used). A pose whose covariance is zero altogether (every dof
 * fixed, e.g. an EKF's pose before its first prediction) has no NEES: run_nees leaves it out and counts
 * it. */
#pragma once

#include <swba/eval/trajectory.h>

#include <mrpt/poses/CPose3D.h>

#include <Eigen/Core>
#include <cstddef>
#include <iosfwd>
#include <string>
#include <vector>

namespace swba::eval
{
/** One row of a covariance file. */
struct CovarianceRow
{
	double stamp = 0;
	Eigen::Matrix3d position = Eigen::Matrix3d::Zero();  ///< world-frame position covariance (m²)
	Eigen::Matrix<double, 6, 6> pose = Eigen::Matrix<double, 6, 6>::Zero();  ///< [ρ, ω] covariance, see above
};

/** Reads a covariance file: per row `stamp`, the 6 upper-triangle entries of the 3×3 position
 * covariance (xx xy xz yy yz zz), then the 21 upper-triangle entries of the 6×6 pose covariance, row
 * by row — 28 numbers; `#` starts a comment line, blank lines are skipped. Throws TrajectoryFileError
 * ("<file>:<line>: <what>") on a wrong count, a non-finite or non-numeric value, a decreasing stamp or
 * a negative diagonal entry (also when the file cannot be opened). */
std::vector<CovarianceRow> read_covariance_file(const std::string& path);
std::vector<CovarianceRow> read_covariance_file(std::istream& in, const std::string& source_name);

/** Writes `rows` in the format read_covariance_file reads (17 significant digits). */
void write_covariance_file(std::ostream& out, const std::vector<CovarianceRow>& rows);

/** A NEES value and the number of degrees of freedom it has. */
struct NeesValue
{
	double value = 0;
	int dof = 0;
};

/** eᵀ·P⁻¹·e over the dofs whose row and column of P are not all zero. Throws std::invalid_argument
 * when e and P differ in size, a dof has a zero diagonal but a non-zero row, or the remaining block is
 * not positive definite (a pivot of its LDLᵀ is not > 0), or no dof remains. */
NeesValue nees(const Eigen::VectorXd& error, const Eigen::MatrixXd& covariance);

/** Position NEES: e = t_true − t_est (world frame) with the 3×3 position covariance. */
NeesValue position_nees(const mrpt::poses::CPose3D& estimate, const mrpt::poses::CPose3D& truth,
						const Eigen::Matrix3d& covariance);

/** δ = [R_estᵀ(t_true − t_est), Log(R_estᵀ·R_true)]: the right-perturbation tangent error. */
Eigen::Matrix<double, 6, 1> pose_error_tangent(const mrpt::poses::CPose3D& estimate, const mrpt::poses::CPose3D& truth);

/** Pose NEES: δ (pose_error_tangent) with the 6×6 pose covariance. */
NeesValue pose_nees(const mrpt::poses::CPose3D& estimate, const mrpt::poses::CPose3D& truth,
					const Eigen::Matrix<double, 6, 6>& covariance);

/** The NEES of one run of one estimator, per pose of the estimate. */
struct RunNees
{
	std::vector<double> stamps;
	std::vector<NeesValue> position, pose;
	/** Poses left out because their position and pose covariances are both zero (every dof fixed). */
	std::size_t fixed_poses = 0;
};

/** NEES of `estimate` (stamps t = k + 1, paired with ground-truth row k + 1 as in ground_truth.h) with
 * the covariance rows `covariance` (one per estimate pose, same stamps), against `ground_truth` rows
 * expressed relative to row 0. A pose whose two covariances are zero is left out (fixed_poses). `source`
 * (the covariance file) names errors: a row count or stamp that differs from the estimate's, a missing
 * ground-truth row, a covariance that is not positive definite, one of the two covariances zero and the
 * other not ("<source>: row <n>: …"). Throws std::runtime_error. */
RunNees run_nees(const Trajectory& estimate, const std::vector<CovarianceRow>& covariance,
				 const std::vector<mrpt::poses::CPose3D>& ground_truth, const std::string& source);

/** The two-sided `probability` χ² band of the average of `runs` NEES values with `dof_sum` dof in
 * total: [χ²_{dof_sum}((1−p)/2) / runs, χ²_{dof_sum}((1+p)/2) / runs]. For runs = 50, 3 dof each
 * (dof_sum 150): [2.36, 3.72]. Throws std::invalid_argument on runs or dof_sum < 1, p ∉ (0, 1). */
struct NeesBand
{
	double low = 0, high = 0;
};
NeesBand nees_band(std::size_t runs, int dof_sum, double probability = 0.95);

/** One NEES quantity (position or pose) averaged over the runs, per step. */
struct AverageNeesSeries
{
	std::vector<double> mean;	 ///< (1/n) Σ NEES over the runs that have the step
	std::vector<int> dof_sum;	 ///< Σ dof over those runs
	std::vector<NeesBand> band;	 ///< the 95 % band of the mean
	/** Share of steps whose mean lies in its band, and the mean over the steps of `mean`. */
	double share_in_band = 0, mean_over_steps = 0;
};

/** The NEES of one estimator averaged over runs, per stamp. */
struct AverageNees
{
	std::vector<double> stamps;
	std::vector<std::size_t> runs;	///< runs that have the step
	AverageNeesSeries position, pose;
};

/** Averages `runs` (summed in the given order, so the result does not depend on how the runs were
 * scheduled) over the union of their stamps, each step over the runs that have it. Empty `runs` give
 * an empty result. */
AverageNees average_nees(const std::vector<RunNees>& runs, double probability = 0.95);
}  // namespace swba::eval
