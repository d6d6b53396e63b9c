// Data association of the range-bearing graph: readings without a landmark ID get one before they
// are gated, and readings the gate held on arrival are tested again, both against the landmarks'
// joint prediction (LandmarkPredictor, landmark_prediction.h; doc/association.md).
#include "range_bearing_graph.h"

#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace swba::estimators::detail
{
JointPrediction RangeBearingGraph::predict_jointly(std::size_t k, const std::vector<PredictionTarget>& targets)
{
	const LandmarkPredictor predictor(smoother_.problem(), poses_, model_, opt_.landmarks == LandmarkParameterization::Xyz);
	const LandmarkPredictor::Group g = predictor.group(k, targets);
	CovarianceRequest request;
	request.groups.push_back(g.vars);
	return predictor.predict(k, targets, g, covariances(request));
}

void RangeBearingGraph::retest_held(std::size_t k, StepSummary& sum)
{
	std::vector<PredictionTarget> targets;
	std::vector<Landmark*> holding;
	for (auto& [id, lm] : store_)
		for (const auto& h : lm.held)
			if (h.pose_step == k)
			{
				targets.push_back({&lm, nullptr});
				holding.push_back(&lm);
				break;
			}
	if (targets.empty()) return;
	const JointPrediction pred = predict_jointly(k, targets);
	if (!pred.ok) return;  // they stay held (counted), re-tested after the solve
	const int dim = reading_dof();
	for (std::size_t j = 0; j < holding.size(); j++)
	{
		Landmark& lm = *holding[j];
		const Eigen::MatrixXd S = pred.covariance_of(static_cast<int>(j), static_cast<int>(j), dim);
		std::vector<Observation> still;
		for (const auto& h : lm.held)
		{
			if (h.pose_step == k &&
				mahalanobis(reading_point(h.z).head(dim), reading_point_covariance(h.z, h.sigma).topLeftCorner(dim, dim),
							pred.points[j], S) <= gate_.threshold())
			{
				admit(lm, h);
				sum.gated--;
				counts_.gated--;
			}
			else
				still.push_back(h);
		}
		lm.held = std::move(still);
	}
}

void RangeBearingGraph::associate_readings(std::vector<std::pair<std::int32_t, Observation>>& readings,
										   std::vector<std::int32_t>& assigned, std::vector<bool>& matched)
{
	const std::size_t k = readings.front().second.pose_step;
	std::vector<std::int32_t> ids;
	const std::vector<PredictionTarget> cand = association_candidates(ids);
	const JointPrediction pred = predict_jointly(k, cand);
	if (!pred.ok)
		throw std::runtime_error("data association at step " + std::to_string(k) +
								 ": the window's covariance cannot be recovered (" + pred.message + ")");
	ReadingMatch match =
		match_readings(readings, pred, cand.size(), association_, opt_.gate_probability, reading_dof());
	if (match.search_cut) counts_.association_cut++;
	if (opt_.association_pose_inflation > 1)
		counts_.rematched += rematch_with_inflated_pose(readings, cand, pred, k, match);
	assigned.clear();
	matched.assign(readings.size(), false);
	for (std::size_t i = 0; i < readings.size(); i++)
	{
		std::set<std::int32_t> choices;  // a provisional landmark stands in cand once per waiting reading
		for (int j : match.compatible[i]) choices.insert(ids[static_cast<std::size_t>(j)]);
		if (choices.size() >= 2) counts_.ambiguous++;
		const int target = match.target[i];
		matched[i] = target >= 0;
		const std::int32_t id = matched[i] ? ids[static_cast<std::size_t>(target)] : next_landmark_id_++;
		readings[i].first = id;
		assigned.push_back(id);
	}
}

std::size_t RangeBearingGraph::rematch_with_inflated_pose(
	const std::vector<std::pair<std::int32_t, Observation>>& readings, const std::vector<PredictionTarget>& cand,
	const JointPrediction& pred, std::size_t k, ReadingMatch& match) const
{
	std::vector<std::size_t> unmatched;
	std::vector<std::pair<std::int32_t, Observation>> again;
	std::set<int> taken;
	for (std::size_t i = 0; i < readings.size(); i++)
		if (match.target[i] < 0)
		{
			unmatched.push_back(i);
			again.push_back(readings[i]);
		}
		else
			taken.insert(match.target[i]);
	if (unmatched.empty()) return 0;
	const int pose_dim = smoother_.problem().variable(poses_[k].var).manifold->tangent_size();
	const JointPrediction wider = with_pose_covariance_scaled(pred, pose_dim, opt_.association_pose_inflation);
	const ReadingMatch second =
		match_readings(again, wider, cand.size(), association_, opt_.gate_probability, reading_dof());
	std::size_t n = 0;
	for (std::size_t u = 0; u < unmatched.size(); u++)
	{
		const int j = second.target[u];
		if (j < 0 || !cand[static_cast<std::size_t>(j)].lm || !taken.insert(j).second) continue;
		match.target[unmatched[u]] = j;
		n++;
	}
	return n;
}

std::vector<PredictionTarget> RangeBearingGraph::association_candidates(
	std::vector<std::int32_t>& ids) const
{
	// The graph's landmarks, the first readings still waiting for confirmation (provisional landmarks:
	// a world point from one reading at a window pose) and the map's landmarks (map policy: their
	// marginals, independent of the window, as the map keeps them).
	std::vector<PredictionTarget> cand;
	for (const auto& [id, lm] : store_)
	{
		ids.push_back(id);
		cand.push_back({&lm, nullptr});
	}
	for (const auto& [id, waiting] : store_.unconfirmed())
		for (const auto& o : waiting)
		{
			ids.push_back(id);
			cand.push_back({nullptr, &o});
		}
	for (const auto& [id, m] : store_.map())
	{
		ids.push_back(id);
		cand.push_back({nullptr, nullptr, &m});
	}
	return cand;
}
}  // namespace swba::estimators::detail
