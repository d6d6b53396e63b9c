// APE / RPE end to end, as evo_ape / evo_rpe.
#include "swba/eval/evaluation.h"

#include <stdexcept>

namespace swba::eval
{
std::string ape_metric_title(PoseRelation r)
{
	return "APE w.r.t. " + pose_relation_description(r) + " (" + pose_relation_unit(r) + ")";
}

std::string rpe_metric_title(PoseRelation r, std::size_t delta, bool all_pairs)
{
	return "RPE w.r.t. " + pose_relation_description(r) + " (" + pose_relation_unit(r) + ")\nfor delta = " +
		   std::to_string(delta) + " (frames) using " + (all_pairs ? "all pairs" : "consecutive pairs");
}

namespace
{
void check_inputs(const Trajectory& ref, const Trajectory& est)
{
	if (ref.empty()) throw std::invalid_argument("the reference trajectory has no poses");
	if (est.empty()) throw std::invalid_argument("the estimated trajectory has no poses");
}

/** The part APE and RPE share: the poses associated and aligned, the relation and its unit (`Options`:
 * ApeOptions or RpeOptions). */
template <class Options>
MetricResult associate_and_align(const char* metric, const Trajectory& ref, const Trajectory& est,
								 const Options& options)
{
	check_inputs(ref, est);
	MetricResult r;
	r.metric = metric;
	r.ref_input_poses = ref.size();
	r.est_input_poses = est.size();
	associate_trajectories(ref, est, options.association, r.ref, r.est);
	r.alignment_options = options.alignment;
	r.alignment = align_trajectory(r.est, r.ref, options.alignment);
	r.relation = options.relation;
	r.unit = pose_relation_unit(options.relation);
	return r;
}
}  // namespace

MetricResult compute_ape(const Trajectory& ref, const Trajectory& est, const ApeOptions& options)
{
	MetricResult r = associate_and_align("APE", ref, est, options);
	r.title = ape_metric_title(options.relation) + "\n" + alignment_title(options.alignment);
	r.errors = ape_errors(r.ref, r.est, options.relation);
	r.pose_ids.resize(r.errors.size());
	for (std::size_t i = 0; i < r.pose_ids.size(); i++) r.pose_ids[i] = i;
	r.stamps = r.est.stamps;
	r.stats = compute_statistics(r.errors);
	return r;
}

MetricResult compute_rpe(const Trajectory& ref, const Trajectory& est, const RpeOptions& options)
{
	MetricResult r = associate_and_align("RPE", ref, est, options);
	r.title = rpe_metric_title(options.relation, options.delta, options.all_pairs) + "\n" +
			  alignment_title(options.alignment);
	const auto pairs = rpe_pairs(r.est.size(), options.delta, options.all_pairs);
	if (pairs.empty())
		throw std::invalid_argument("RPE needs at least delta + 1 = " + std::to_string(options.delta + 1) +
									" associated poses, found " + std::to_string(r.est.size()));
	r.errors = rpe_errors(r.ref, r.est, options.relation, pairs);
	for (const auto& p : pairs)
	{
		r.pose_ids.push_back(p.second);
		r.stamps.push_back(r.est.stamps[p.second]);
	}
	r.stats = compute_statistics(r.errors);
	return r;
}
}  // namespace swba::eval
