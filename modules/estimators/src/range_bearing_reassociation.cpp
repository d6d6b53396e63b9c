// Re-association inside the window: decisions of the data association revisited after each solve
// while their readings' poses are in the window (doc/association.md, "Re-association"). The moves
// are decided by reassociation_moves() and applied here.
#include "range_bearing_graph.h"
#include "reassociation_moves.h"

#include <algorithm>
#include <vector>

namespace swba::estimators::detail
{
void RangeBearingGraph::reassociate(StepSummary& sum)
{
	if (association_ == DataAssociation::Ids || association_ == DataAssociation::Auto || !opt_.reassociate) return;
	const auto distance = [this](const Landmark& lm, const Observation& o) { return gate_distance(lm, o, nullptr); };
	const auto position = [this](const Landmark& lm) { return world_position(lm); };
	const auto in_prior = [this](VariableId v) { return smoother_.in_prior(v); };
	const std::vector<ReadingMove> moves =
		reassociation_moves({store_, distance, position, in_prior, gate_.threshold(), reading_dof()});
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
