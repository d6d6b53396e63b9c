/** \file landmark_store.h
 * (private to the estimators module) The landmarks of the range-bearing graph and the bookkeeping of
 * their readings, apart from the factors and variables that represent them: the records by ID and the
 * index from variable to ID, the readings of the linear tail's poses that still count for a landmark's
 * gate, the first readings of landmarks not yet confirmed, and the map policy's map. The store never
 * touches the smoother's problem: RangeBearingGraph adds and removes the variables and factors and
 * tells the store. */
#pragma once

#include <swba/factors/range_bearing.h>
#include <swba/nonlinear/problem.h>

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <deque>
#include <map>
#include <set>
#include <utility>
#include <vector>

namespace swba::estimators::detail
{
struct Observation
{
	std::size_t pose_step;  ///< index into RangeBearingGraph::poses() (0 = initial pose)
	RangeBearingMeasurement z;
	Eigen::Vector3d sigma;
	FactorId factor = -1;
	std::size_t reading = 0;  ///< index among its step's readings (assigned_ids()[pose_step][reading])
};

struct Landmark
{
	std::int32_t id;
	VariableId var;
	std::size_t anchor_step = 0;  ///< inverse depth only
	/** Inverse-depth mode: the landmark was in the marginal prior when its anchor left the window, so it
	 * was switched to world XYZ (a parameterisation no later marginalisation has to change). */
	bool world_xyz = false;
	std::vector<Observation> obs;  ///< observations whose factors are still in the problem
	/** Readings of poses in the smoother's linear tail (still in the window W, no longer factors). */
	std::size_t tail_readings = 0;
	/** Readings held out by the χ² gate whose pose is still in the window (no factor). */
	std::vector<Observation> held;
};

/** Map policy: a landmark that left the state, as its marginal when it left. */
struct MapLandmark
{
	Eigen::Vector3d position;
	Eigen::Matrix3d covariance;  ///< of the world position (planar: z row and column zero)
};

class LandmarkStore
{
   public:
	using Records = std::map<std::int32_t, Landmark>;

	/** @name Landmarks in the state, by ID (iteration in increasing ID order)
	 * @{ */
	/** Adds `lm`, whose ID is not in the store, and indexes its variable. */
	Landmark& add(Landmark lm);
	Landmark* find(std::int32_t id);
	const Landmark* find(std::int32_t id) const;
	/** The landmark `id` (throws std::out_of_range when there is none). */
	Landmark& at(std::int32_t id) { return records_.at(id); }
	const Landmark& at(std::int32_t id) const { return records_.at(id); }
	/** The landmark of variable `v`, or null when `v` is no landmark's. */
	const Landmark* find_by_variable(VariableId v) const;
	bool is_landmark(VariableId v) const { return id_of_var_.count(v) > 0; }
	std::size_t size() const { return records_.size(); }
	Records::iterator begin() { return records_.begin(); }
	Records::iterator end() { return records_.end(); }
	Records::const_iterator begin() const { return records_.begin(); }
	Records::const_iterator end() const { return records_.end(); }
	/** Moves landmark `lm` onto variable `v` (its new parameterisation): the index follows. */
	void rebind(Landmark& lm, VariableId v);
	/** Forgets the landmark of variable `v`; returns how many readings it still held (they are dropped
	 * for good), or false when `v` is no landmark's. */
	bool forget(VariableId v, std::size_t& held);
	/** Drops the observations whose factors are in `removed`. */
	void forget_observations(const std::set<FactorId>& removed);
	/** @} */

	/** @name Readings of the linear tail's poses
	 * @{ */
	/** Readings of `lm` in the window W: its factors' and those of the linear tail's poses. */
	static std::size_t window_readings(const Landmark& lm) { return lm.obs.size() + lm.tail_readings; }
	/** The readings of pose step k (leaving the re-linearised poses for the linear tail) still count
	 * for their landmarks' window_readings until release_tail_readings(). */
	void hold_tail_readings(std::size_t k);
	/** The oldest pose of the linear tail left the window: its readings no longer count. */
	void release_tail_readings();
	/** @} */

	/** @name Readings dropped for good
	 * @{ */
	/** How many readings a drop removed: held by the gate, and unconfirmed first readings. */
	struct Dropped
	{
		std::size_t held = 0;
		std::size_t unconfirmed = 0;
	};
	/** Drops the held readings and the unconfirmed first readings of pose step `k` (leaving the window). */
	Dropped drop_readings_at(std::size_t k);
	/** Drops every held reading and unconfirmed first reading (the run is over). */
	Dropped drop_pending();
	/** @} */

	/** @name First readings of landmarks not yet in the state, waiting for a consistent second reading
	 * @{ */
	/** The first readings waiting under `id`, oldest first; an empty list is created when there is none. */
	std::vector<Observation>& waiting(std::int32_t id) { return unconfirmed_[id]; }
	/** The waiting readings of `id`, or null. */
	const std::vector<Observation>* find_waiting(std::int32_t id) const;
	/** Forgets the waiting readings of `id` (its landmark was confirmed). */
	void confirm(std::int32_t id) { unconfirmed_.erase(id); }
	const std::map<std::int32_t, std::vector<Observation>>& unconfirmed() const { return unconfirmed_; }
	/** @} */

	/** @name Map policy: landmarks that left the state, as their marginals
	 * @{ */
	const std::map<std::int32_t, MapLandmark>& map() const { return map_; }
	bool in_map(std::int32_t id) const { return map_.count(id) > 0; }
	/** Keeps landmark `id`'s marginal in the map (replacing an older one). */
	void keep_in_map(std::int32_t id, const MapLandmark& m) { map_[id] = m; }
	/** Removes landmark `id` from the map and returns its marginal (it re-enters the state). */
	MapLandmark take_from_map(std::int32_t id);
	/** @} */

   private:
	Records records_;
	std::map<VariableId, std::int32_t> id_of_var_;
	/** Per pose of the linear tail, oldest first: the landmarks it read and how often. */
	std::deque<std::vector<std::pair<std::int32_t, std::size_t>>> tail_readings_;
	std::map<std::int32_t, std::vector<Observation>> unconfirmed_;
	std::map<std::int32_t, MapLandmark> map_;
};
}  // namespace swba::estimators::detail
