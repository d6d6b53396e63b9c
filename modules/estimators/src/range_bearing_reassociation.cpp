// Re-association inside the window: decisions of the data association revisited after each solve
// while their readings' poses are in the window (doc/association.md, "Re-association").
#include "range_bearing_graph.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <vector>

namespace swba::estimators::detail
{
std::map<std::int32_t, std::set<std::size_t>> RangeBearingGraph::steps_seen() const
{
	std::map<std::int32_t, std::set<std::size_t>> seen;
	for (const auto& [id, lm] : store_)
	{
		auto& steps = seen[id];
		for (const auto& o : lm.obs) steps.insert(o.pose_step);
		for (const auto& h : lm.held) steps.insert(h.pose_step);
	}
	return seen;
}

std::vector<RangeBearingGraph::ReadingMove> RangeBearingGraph::misfit_moves(
	std::map<std::int32_t, std::set<std::size_t>>& seen_at) const
{
	std::vector<ReadingMove> moves;
	for (const auto& [id, lm] : store_)
		for (const auto& o : lm.obs)
		{
			if (gate_distance(lm, o, nullptr) <= gate_.threshold()) continue;
			std::int32_t best = -1;
			double best_d2 = gate_.threshold();
			for (const auto& [other, cand] : store_)
			{
				if (other == id || seen_at[other].count(o.pose_step)) continue;
				const double d2 = gate_distance(cand, o, nullptr);
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

std::vector<RangeBearingGraph::ReadingMove> RangeBearingGraph::duplicate_merges(
	const std::map<std::int32_t, std::set<std::size_t>>& seen_at, const std::vector<ReadingMove>& moved) const
{
	std::set<std::int32_t> busy;  // landmarks a move of this step already changes
	for (const ReadingMove& m : moved) busy.insert({m.from, m.to});
	std::map<std::int32_t, Eigen::Vector3d> at;
	for (const auto& [id, lm] : store_) at[id] = world_position(lm);
	const auto shares_a_step = [](const std::set<std::size_t>& a, const std::set<std::size_t>& b) {
		for (std::size_t k : a)
			if (b.count(k)) return true;
		return false;
	};
	std::vector<ReadingMove> merges;
	for (const auto& [id, lm] : store_)
	{
		if (lm.obs.empty() || !lm.held.empty() || busy.count(id)) continue;
		if (smoother_.in_prior(lm.var)) continue;  // its information is in the prior
		// A reading within the gate of both landmarks puts them at most 2·√(2·gate) Cartesian σ apart.
		const Observation& last = lm.obs.back();
		double s = std::max(last.sigma[0], last.z.range * last.sigma[1]);
		if (reading_dof() == 3) s = std::max(s, last.z.range * last.sigma[2]);
		const double reach = 2 * std::sqrt(2 * gate_.threshold()) * s;
		std::int32_t best = -1;
		double best_sum = std::numeric_limits<double>::infinity();
		for (const auto& [other, cand] : store_)
		{
			if (other >= id) break;  // into an older landmark only (IDs grow with creation)
			if (busy.count(other) || (at.at(other) - at.at(id)).norm() > reach ||
				shares_a_step(seen_at.at(id), seen_at.at(other)))
				continue;
			double sum_d2 = 0;
			for (const auto& o : lm.obs)
			{
				const double d2 = gate_distance(cand, o, nullptr);
				if (!(d2 <= gate_.threshold()))
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

void RangeBearingGraph::reassociate(StepSummary& sum)
{
	if (association_ == DataAssociation::Ids || association_ == DataAssociation::Auto || !opt_.reassociate) return;
	std::map<std::int32_t, std::set<std::size_t>> seen_at = steps_seen();
	std::vector<ReadingMove> moves = misfit_moves(seen_at);
	const std::vector<ReadingMove> merges = duplicate_merges(seen_at, moves);
	moves.insert(moves.end(), merges.begin(), merges.end());
	Problem& problem = smoother_.problem();
	for (const ReadingMove& m : moves)
	{
		Landmark& from = store_.at(m.from);
		const auto it = std::find_if(from.obs.begin(), from.obs.end(), [&](const Observation& o) { return o.factor == m.factor; });
		Observation o = *it;
		from.obs.erase(it);
		problem.remove_factor(o.factor);
		assigned_ids_.at(o.pose_step).at(o.reading) = m.to;
		admit(store_.at(m.to), o);
		sum.reassociated++;
		counts_.reassociated++;
	}
	// A landmark left with no reading is determined by nothing but the marginal prior, if it is in it;
	// otherwise it is no longer a landmark of the estimate.
	for (const ReadingMove& m : moves)
	{
		const Landmark* lm = store_.find(m.from);
		if (!lm || !lm->obs.empty()) continue;
		if (smoother_.in_prior(lm->var)) continue;
		const VariableId v = lm->var;
		forget_landmark(v);
		smoother_.problem().remove_variable(v);
	}
}
}  // namespace swba::estimators::detail
