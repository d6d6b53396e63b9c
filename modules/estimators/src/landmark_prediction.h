/** \file landmark_prediction.h
 * (private to the estimators module) Landmarks predicted in the sensor frame of a pose with their
 * joint covariance, what data association and the re-test of held readings compare readings with:
 * the graph's landmarks, provisional ones (a first reading waiting for confirmation) and the map
 * policy's; and the association of a step's readings with them (match_readings). The predictor reads
 * the problem's values and the poses; the joint covariance of the variables it names comes from the
 * caller (RangeBearingGraph::covariances, which holds the free gauge). */
#pragma once

#include "landmark_store.h"

#include <swba/estimators/data_association.h>
#include <swba/estimators/pose_model.h>
#include <swba/nonlinear/covariance.h>
#include <swba/nonlinear/problem.h>

#include <mrpt/poses/CPose3D.h>

#include <Eigen/Core>

#include <cstddef>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace swba::estimators::detail
{
struct PoseRecord
{
	double time;
	VariableId var;
	mrpt::poses::CPose3D sensor;  ///< sensor pose on the robot at this step
};

/** A reading as a point in the sensor frame (the measurement model's inverse at the identity). */
Eigen::Vector3d reading_point(const RangeBearingMeasurement& z);
/** Covariance of reading_point(z) for the noise σ = (range, yaw, pitch) (central differences). */
Eigen::Matrix3d reading_point_covariance(const RangeBearingMeasurement& z, const Eigen::Vector3d& sigma);
/** Squared Mahalanobis distance of a reading (point `z`, covariance `R`, both reading_dof-sized) from a
 * prediction (point `y`, its block `S` of the predictions' joint covariance). */
double mahalanobis(const Eigen::VectorXd& z, const Eigen::MatrixXd& R, const Eigen::Vector3d& y, const Eigen::MatrixXd& S);

/** What a prediction predicts: a graph landmark, a provisional one (its first reading), or a landmark
 * of the map (map policy; its marginal is its own noise, it depends on no window variable). */
struct PredictionTarget
{
	const Landmark* lm;
	const Observation* first;
	const MapLandmark* map = nullptr;
};

/** Targets predicted in the sensor frame of pose step k (at its current value) with their joint
 * covariance: Jacobian × the joint covariance of the new pose and the variables the targets depend on
 * × Jacobianᵀ, plus a provisional or map target's own noise. */
struct JointPrediction
{
	bool ok = false;
	std::string message;                  ///< why the covariance could not be recovered
	std::vector<Eigen::Vector3d> points;  ///< per target, in the sensor frame
	Eigen::MatrixXd jacobian;             ///< (targets × reading_dof) × the group's tangent
	Eigen::MatrixXd covariance;           ///< the group's joint covariance
	std::vector<Eigen::MatrixXd> own;     ///< per target, noise that is not a window variable's
	/** Per target, the column ranges (first, size) of `jacobian` its rows may be non-zero in: the new
	 * pose's and its own variables'. */
	std::vector<std::vector<std::pair<int, int>>> support;
	/** The reading_dof-sized block (a, b) of the predictions' joint covariance,
	 * J_a Σ J_bᵀ over the two targets' supports only (O(dim² · support²), not O(dim · D²)). */
	Eigen::MatrixXd covariance_of(int a, int b, int dim) const;
};

/** `pred` with the new pose's covariance (the group's leading `pose_dim` block) multiplied by `factor`
 * (≥ 1) and its correlations with the other variables unchanged: an independent pose error of
 * (factor − 1) times the pose's covariance added, the landmarks' own uncertainty as it was. */
JointPrediction with_pose_covariance_scaled(JointPrediction pred, int pose_dim, double factor);

/** What match_readings decided, per reading. */
struct ReadingMatch
{
	std::vector<int> target;  ///< the index of its target, or −1 (unmatched)
	/** The targets individually compatible with it (inside the χ² gate), nearest first: the choice the
	 * association had (a reading compatible with two landmarks or more is ambiguous on its own). */
	std::vector<std::vector<int>> compatible;
	bool search_cut = false;  ///< JCBB's search stopped at its node budget (associate)
};

/** Data association of one step's `readings` (ID field ignored) with the `num_candidates` targets of
 * `pred` by `method` (NearestNeighbour or Jcbb), readings and predictions as points in the sensor
 * frame (`dim` = reading_dof rows). Only the targets individually compatible (χ² quantile at
 * `probability`) with some reading, each reading keeping its few nearest, enter the association
 * problem. */
ReadingMatch match_readings(const std::vector<std::pair<std::int32_t, Observation>>& readings,
							const JointPrediction& pred, std::size_t num_candidates, DataAssociation method,
							double probability, int dim);

class LandmarkPredictor
{
   public:
	/** Over the values of `problem` and the `poses` (by step), for readings of `model`;
	 * `xyz_landmarks`: every landmark is a world point (else inverse depth unless switched). */
	LandmarkPredictor(const Problem& problem, const std::vector<PoseRecord>& poses, PoseModel model, bool xyz_landmarks)
		: problem_(problem), poses_(poses), model_(model), xyz_landmarks_(xyz_landmarks)
	{
	}

	/** The variables of a joint prediction at pose step k: the pose's, then each target's in turn. */
	struct Group
	{
		std::vector<VariableId> vars;               ///< in tangent order
		std::map<VariableId, int> at;               ///< first column of each in the group's tangent
		std::vector<std::vector<VariableId>> of_target;  ///< per target, the variables it depends on
		int dim = 0;                                ///< the group's tangent size
	};
	Group group(std::size_t k, const std::vector<PredictionTarget>& targets) const;
	/** The prediction of `targets` at pose step k, given `cov`, the covariance of group(k, targets)'s
	 * variables as one group (not ok, with its message, when that failed). */
	JointPrediction predict(std::size_t k, const std::vector<PredictionTarget>& targets, const Group& g,
							const CovarianceResult& cov) const;

   private:
	int reading_dof() const { return estimators::reading_dof(model_); }
	bool is_world_point(const Landmark& lm) const { return xyz_landmarks_ || lm.world_xyz; }
	/** predict() for target j. */
	void predict_one(std::size_t k, const PredictionTarget& t, const Group& g, int j, JointPrediction& out) const;
	/** The rows of target `t`'s prediction (sensor frame of pose step k) over the tangent of variable
	 * `v`, by central differences, written into `J` (reading_dof × v's tangent size). */
	void target_jacobian(std::size_t k, const PredictionTarget& t, VariableId v, Eigen::Ref<Eigen::MatrixXd> J) const;
	/** The window variables target `t`'s world point depends on. */
	std::vector<VariableId> target_variables(const PredictionTarget& t) const;
	/** Target `t` in the sensor frame of pose step k, with variable `v` at `xv` (v < 0: every variable
	 * at its current value; pose k's is its dead-reckoned one before the step's solve). */
	Eigen::Vector3d predict_target(std::size_t k, const PredictionTarget& t, VariableId v, const double* xv) const;
	/** A provisional target's noise in the sensor frame of pose step k: its first reading's, rotated
	 * (reading_dof-sized). */
	Eigen::MatrixXd provisional_noise(std::size_t k, const Observation& first) const;
	/** A map target's noise in the sensor frame of pose step k: its map covariance, rotated
	 * (reading_dof-sized). */
	Eigen::MatrixXd map_noise(std::size_t k, const MapLandmark& m) const;
	/** The sensor's pose in the world at pose step k (the pose's current value). */
	mrpt::poses::CPose3D sensor_in_world(std::size_t k) const;

	const Problem& problem_;
	const std::vector<PoseRecord>& poses_;
	PoseModel model_;
	bool xyz_landmarks_;
};
}  // namespace swba::estimators::detail
