/** \file reading_gate.h
 * (private to the estimators module) The χ² gate of range-bearing readings: the squared Mahalanobis
 * distance of a reading from a landmark's world point, and the newest pose's prediction the readings
 * of a step are tested at on arrival (its odometry-only covariance and a robust centre). The gate
 * holds no graph: callers pass the pose value, the sensor on the robot and the landmark's point, so
 * its maths can be read and tested alone. Which readings are tested when, and what happens to those
 * outside, is RangeBearingGraph's (range_bearing_gate.cpp; doc/outliers.md). */
#pragma once

#include "landmark_store.h"

#include <swba/core/factor.h>
#include <swba/core/manifold.h>
#include <swba/estimators/pose_model.h>

#include <mrpt/poses/CPose3D.h>

#include <Eigen/Core>

#include <cstddef>
#include <memory>
#include <vector>

namespace swba::estimators::detail
{
/** Reading factor `f` (rows range, yaw, pitch; variables pose, point) as `model` takes it, with the
 * information of the sensor noise `sigma` of the rows kept: planar keeps rows (range, yaw) on pose
 * (ρx, ρy, ωz) and landmark (x, y) (a 2D sensor measures no pitch; its row is identically 0 on the
 * plane). */
std::shared_ptr<Factor> model_reading_factor(PoseModel model, std::shared_ptr<Factor> f, const Eigen::VectorXd& sigma);

/** A reading of the newest step and the landmark it is tested against. */
struct GatedReading
{
	Eigen::Vector3d point;  ///< the landmark's world position
	std::size_t n;          ///< readings its estimate averages (LandmarkStore::window_readings)
	const Observation* o;
};

class ReadingGate
{
   public:
	using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

	ReadingGate() = default;
	/** A gate for readings of `model` (Spatial or Planar: reading_dof rows) with χ² bound `threshold`. */
	ReadingGate(PoseModel model, double threshold) : model_(model), threshold_(threshold) {}

	/** χ²_dof(gate_probability): a reading is inside the gate when its distance is at most this. */
	double threshold() const { return threshold_; }
	/** The sensor noise of the rows the model keeps: (range, yaw, pitch), planar (range, yaw). */
	Eigen::VectorXd reading_sigma(const Observation& o) const { return o.sigma.head(reading_dof(model_)); }

	/** Residual (reading_dof rows, not whitened) of reading `o`, taken from `sensor` on the robot at
	 * pose value `pose_x`, against world point `p`, and optionally ∂r/∂T on the pose's tangent. False
	 * when the model is undefined there. */
	bool residual(const Eigen::Vector3d& p, const Observation& o, const mrpt::poses::CPose3D& sensor,
				  const double* pose_x, Eigen::VectorXd& r, RowMajorMatrix* JT) const;
	/** Squared Mahalanobis distance of reading `o` (from `sensor` at pose value `pose_x`) against the
	 * world point `p`, whose estimate averages `n` readings. Innovation covariance: the sensor noise R,
	 * the point's R/n (an approximation that avoids a marginal covariance), and the pose's `pose_cov`
	 * (on the pose variable's tangent; null: none) through ∂h/∂T. Infinite where the model is
	 * undefined. */
	double distance(const Eigen::Vector3d& p, std::size_t n, const Observation& o, const mrpt::poses::CPose3D& sensor,
					const double* pose_x, const Eigen::MatrixXd* pose_cov) const;

	/** @name The newest pose's prediction, which readings are tested at on arrival
	 * @{ */
	/** Odometry covariance of the newest pose relative to the previous one, on the pose variable's
	 * tangent (the inverse of its odometry factor's information). */
	void set_prediction_covariance(Eigen::MatrixXd cov) { newest_pose_cov_ = std::move(cov); }
	const Eigen::MatrixXd& prediction_covariance() const { return newest_pose_cov_; }
	/** Sets centre(): the newest pose (manifold `M`, predicted value `x0`, covariance
	 * prediction_covariance()) estimated from its prediction and `readings` (all taken from `sensor`),
	 * their landmarks held at their points, under a Cauchy loss at the gate's radius (Gauss-Newton,
	 * ≤ 10 iterations). Gating at the dead-reckoned pose instead holds every good reading of a step
	 * whose odometry drew a 3-4σ error (each reading then sits at the gate's edge, all sharing one pose
	 * error), and the pose is left to odometry alone; the robust centre follows the readings' consensus
	 * and a gross reading still falls outside. */
	void centre_on(const Manifold& M, const double* x0, const mrpt::poses::CPose3D& sensor,
				   const std::vector<GatedReading>& readings);
	/** The newest pose's value the gate tests its readings at (null before the first centre_on). */
	const double* centre() const { return centre_.empty() ? nullptr : centre_.data(); }
	/** @} */

   private:
	PoseModel model_ = PoseModel::Spatial;
	double threshold_ = 0;
	Eigen::MatrixXd newest_pose_cov_;
	std::vector<double> centre_;
};
}  // namespace swba::estimators::detail
