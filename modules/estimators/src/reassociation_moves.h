/** \file reassociation_moves.h
 * (private to the estimators module) Re-association's decisions inside the window, apart from the
 * graph: after a solve, which readings move to another landmark (a reading outside its landmark's χ²
 * gate and inside another's) and which landmarks are duplicates to merge into an older one (all
 * their readings inside its gate). The graph applies the moves (RangeBearingGraph::reassociate);
 * doc/association.md, "Re-association". */
#pragma once

#include "landmark_store.h"

#include <Eigen/Core>

#include <cstdint>
#include <functional>
#include <vector>

namespace swba::estimators::detail
{
/** A reading (by its factor) that re-association moves from one landmark to another. */
struct ReadingMove
{
	std::int32_t from, to;
	FactorId factor;
};

/** What re-association reads of the graph: its landmarks and, at the current estimate, the gate. */
struct ReassociationInputs
{
	const LandmarkStore& landmarks;
	/** The χ² gate's squared distance of a reading against a landmark (no pose covariance). */
	std::function<double(const Landmark&, const Observation&)> distance;
	/** A landmark's world position. */
	std::function<Eigen::Vector3d(const Landmark&)> position;
	/** Whether a landmark's variable is in the marginal prior (its information is there: never merged). */
	std::function<bool(VariableId)> in_prior;
	double threshold;  ///< the gate's χ² bound
	int reading_dof;   ///< rows of a reading (2 planar, 3)
};

/** The moves of one re-association: first each misfit reading to the other landmark it fits best (one
 * with no reading of the same step: a scan sees a landmark once), then each duplicate landmark's
 * readings to the older landmark they all fit best (landmarks a misfit move changes are left for the
 * next step). */
std::vector<ReadingMove> reassociation_moves(const ReassociationInputs& in);
}  // namespace swba::estimators::detail
