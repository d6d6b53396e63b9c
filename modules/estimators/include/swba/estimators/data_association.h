/** \file data_association.h
 * Data association of landmark readings that carry no ID: which reading comes from which landmark
 * of the map. The window predicts every candidate landmark in the new pose's sensor frame (Cartesian,
 * so that bearings never wrap) with the joint covariance of the predictions — correlated through the
 * pose — and decides by nearest neighbour (each reading its closest individually compatible
 * landmark; MRPT's mrpt::slam::data_association_full_covariance) or joint compatibility branch and
 * bound (JCBB, Neira & Tardós 2001: the largest set of pairings that is jointly compatible, the
 * nearest of those; written here, doc/association.md says why not MRPT's). */
#pragma once

#include <swba/core/names.h>

#include <Eigen/Core>

#include <array>
#include <string>
#include <vector>

namespace swba::estimators
{
enum class DataAssociation
{
	/** The readings' own landmark IDs when every reading has one, else Jcbb. */
	Auto,
	Ids,               ///< the readings' landmark IDs (a reading without one is invalid)
	NearestNeighbour,  ///< each reading its nearest individually compatible landmark
	Jcbb               ///< joint compatibility branch and bound
};
constexpr std::array<EnumName<DataAssociation>, 4> enum_names(DataAssociation)
{
	return {{{DataAssociation::Auto, "auto"},
			 {DataAssociation::Ids, "ids"},
			 {DataAssociation::NearestNeighbour, "nn"},
			 {DataAssociation::Jcbb, "jcbb"}}};
}

/** One association problem: M readings and N predicted landmarks, all points of dimension d (3, or 2
 * for the planar model) in the sensor frame. */
struct AssociationProblem
{
	int dim = 3;
	/** The readings as points (M × d) and their noise covariances (d × d each). */
	std::vector<Eigen::VectorXd> readings;
	std::vector<Eigen::MatrixXd> reading_covariances;
	/** The predicted landmarks (N × d) and the joint covariance of the predictions ((N·d) × (N·d)):
	 * the pose's uncertainty (shared, so off-diagonal blocks) plus each landmark's own. */
	std::vector<Eigen::VectorXd> predictions;
	Eigen::MatrixXd prediction_covariance;
};

/** For each reading, the index of the prediction it is associated with, or −1 (unmatched: a new
 * landmark). A prediction takes at most one reading. Pairs are compatible when the squared
 * Mahalanobis distance of their difference, under the prediction's covariance plus the reading's, is
 * within the χ² quantile at `probability` with d degrees of freedom (the individual-compatibility
 * gate; JCBB's joint test uses the quantile of d·k degrees of freedom for k pairs, and of the
 * hypotheses with the most pairs keeps the one of smallest joint distance). `method` is
 * NearestNeighbour or Jcbb (throws std::invalid_argument otherwise). Deterministic. JCBB's search
 * is exponential in the readings: it stops after a fixed number of nodes (20 000) with the best
 * pairing found so far, and sets `*cut` (when given) to say so. */
std::vector<int> associate(const AssociationProblem& problem, DataAssociation method, double probability,
						   bool* cut = nullptr);

/** Squared Mahalanobis distance of reading i to prediction j (the individual-compatibility test). */
double association_distance(const AssociationProblem& problem, int reading, int prediction);
}  // namespace swba::estimators
