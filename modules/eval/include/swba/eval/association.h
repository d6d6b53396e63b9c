/** \file association.h
 * Pairing the poses of two trajectories by time stamp, exactly as evo's
 * sync.associate_trajectories does. */
#pragma once

#include <cstddef>
#include <vector>

#include "swba/eval/trajectory.h"

namespace swba::eval
{
struct AssociationOptions
{
	/** Largest accepted |t_ref − (t_est + t_offset)|, seconds. (Default = 0.01, as evo) */
	double t_max_diff = 0.01;
	/** Added to the estimate's stamps before matching, seconds. (Default = 0) */
	double t_offset = 0.0;
};

/** Matched index pairs: ref.poses[ref_ids[k]] ↔ est.poses[est_ids[k]], in the order of the shorter
 * trajectory (the estimate when both are equally long). */
struct Association
{
	std::vector<std::size_t> ref_ids;
	std::vector<std::size_t> est_ids;
	std::size_t size() const { return ref_ids.size(); }
};

/** evo's rule: the shorter trajectory (the estimate when both are equally long) is walked in order;
 * each of its poses is paired with the pose of the longer one whose (offset) stamp is nearest — the
 * first such pose on ties — and the pair is kept when |Δt| ≤ t_max_diff. A pose of the longer
 * trajectory may be used more than once (duplicate stamps in the shorter one). Never throws; the
 * result may be empty. */
Association associate(const Trajectory& ref, const Trajectory& est, const AssociationOptions& options = {});

/** associate() and return the paired sub-trajectories (same length, pair k at index k); each keeps
 * its own stamps. Throws std::runtime_error when no pair is found (as evo). */
void associate_trajectories(const Trajectory& ref, const Trajectory& est, const AssociationOptions& options,
							Trajectory& ref_out, Trajectory& est_out);
}  // namespace swba::eval
