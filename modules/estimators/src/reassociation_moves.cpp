#include "reassociation_moves.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>

namespace swba::estimators::detail
{
namespace
{
/** The pose steps each landmark has a reading from (admitted or held): a scan sees a landmark once. */
std::map<std::int32_t, std::set<std::size_t>> steps_seen(const LandmarkStore& store)
{
	std::map<std::int32_t, std::set<std::size_t>> seen;
	for (const auto& [id, lm] : store)
	{
		auto& steps = seen[id];
		for (const auto& o : lm.obs) steps.insert(o.pose_step);
		for (const auto& h : lm.held) steps.insert(h.pose_step);
	}
	return seen;
}

/** Readings outside the gate of their landmark and inside another's; `seen_at` gains each move's step. */
std::vector<ReadingMove> misfit_moves(const ReassociationInputs& in,
									  std::map<std::int32_t, std::set<std::size_t>>& seen_at)
{
	std::vector<ReadingMove> moves;
	for (const auto& [id, lm] : in.landmarks)
		for (const auto& o : lm.obs)
		{
			if (in.distance(lm, o) <= in.threshold) continue;
			std::int32_t best = -1;
			double best_d2 = in.threshold;
			for (const auto& [other, cand] : in.landmarks)
			{
				if (other == id || seen_at[other].count(o.pose_step)) continue;
				const double d2 = in.distance(cand, o);
				if (d2 <= best_d2)
				{
					best = other;
					best_d2 = d2;
				}
			}
			if (best < 0) continue;
			moves.push_back({id, best, o.factor});
			seen_at[best].insert(o.pose_step);
		}
	return moves;
}

/** The readings of each duplicate landmark, to the older one they all fit; landmarks that `moved`
 * changes are left for the next step. */
std::vector<ReadingMove> duplicate_merges(const ReassociationInputs& in,
										  const std::map<std::int32_t, std::set<std::size_t>>& seen_at,
										  const std::vector<ReadingMove>& moved)
{
	std::set<std::int32_t> busy;  // landmarks a move of this step already changes
	for (const ReadingMove& m : moved) busy.insert({m.from, m.to});
	std::map<std::int32_t, Eigen::Vector3d> at;
	for (const auto& [id, lm] : in.landmarks) at[id] = in.position(lm);
	const auto shares_a_step = [](const std::set<std::size_t>& a, const std::set<std::size_t>& b) {
		for (std::size_t k : a)
			if (b.count(k)) return true;
		return false;
	};
	std::vector<ReadingMove> merges;
	for (const auto& [id, lm] : in.landmarks)
	{
		if (lm.obs.empty() || !lm.held.empty() || busy.count(id)) continue;
		if (in.in_prior(lm.var)) continue;  // its information is in the prior
		// A reading within the gate of both landmarks puts them at most 2·√(2·gate) Cartesian σ apart.
		const Observation& last = lm.obs.back();
		double s = std::max(last.sigma[0], last.z.range * last.sigma[1]);
		if (in.reading_dof == 3) s = std::max(s, last.z.range * last.sigma[2]);
		const double reach = 2 * std::sqrt(2 * in.threshold) * s;
		std::int32_t best = -1;
		double best_sum = std::numeric_limits<double>::infinity();
		for (const auto& [other, cand] : in.landmarks)
		{
			if (other >= id) break;  // into an older landmark only (IDs grow with creation)
			if (busy.count(other) || (at.at(other) - at.at(id)).norm() > reach ||
				shares_a_step(seen_at.at(id), seen_at.at(other)))
				continue;
			double sum_d2 = 0;
			for (const auto& o : lm.obs)
			{
				const double d2 = in.distance(cand, o);
				if (!(d2 <= in.threshold))
				{
					sum_d2 = std::numeric_limits<double>::infinity();
					break;
				}
				sum_d2 += d2;
			}
			if (sum_d2 < best_sum)
			{
				best = other;
				best_sum = sum_d2;
			}
		}
		if (best < 0) continue;
		for (const auto& o : lm.obs) merges.push_back({id, best, o.factor});
		busy.insert({id, best});
	}
	return merges;
}
}  // namespace

std::vector<ReadingMove> reassociation_moves(const ReassociationInputs& in)
{
	std::map<std::int32_t, std::set<std::size_t>> seen_at = steps_seen(in.landmarks);
	std::vector<ReadingMove> moves = misfit_moves(in, seen_at);
	const std::vector<ReadingMove> merges = duplicate_merges(in, seen_at, moves);
	moves.insert(moves.end(), merges.begin(), merges.end());
	return moves;
}
}  // namespace swba::estimators::detail
