/** \file evaluation.h
 * APE and RPE of an estimated trajectory against a reference, end to end (associate → align →
 * errors → statistics), with evo's semantics and titles. */
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "swba/eval/alignment.h"
#include "swba/eval/association.h"
#include "swba/eval/metrics.h"
#include "swba/eval/trajectory.h"

namespace swba::eval
{
struct ApeOptions
{
	PoseRelation relation = PoseRelation::TranslationPart;  ///< (Default = translation part)
	AlignmentOptions alignment;								 ///< (Default = not aligned)
	AssociationOptions association;						 ///< (Default = t_max_diff 0.01 s, no offset)
};

struct RpeOptions
{
	PoseRelation relation = PoseRelation::TranslationPart;  ///< (Default = translation part)
	std::size_t delta = 1;  ///< frames between the two poses of a pair. (Default = 1)
	bool all_pairs = false;  ///< pairs (i, i+δ) for every i instead of consecutive ones. (Default = false)
	AlignmentOptions alignment;
	AssociationOptions association;
};

/** The outcome of compute_ape() / compute_rpe(). */
struct MetricResult
{
	std::string metric;  ///< "APE" or "RPE"
	/** evo's title, e.g. "APE w.r.t. translation part (m)\n(not aligned)". */
	std::string title;
	PoseRelation relation = PoseRelation::TranslationPart;
	std::string unit;			   ///< "m", "deg", "rad", "unit-less"
	AlignmentOptions alignment_options;
	AlignmentResult alignment;	   ///< what was applied to the estimate
	std::size_t ref_input_poses = 0, est_input_poses = 0;  ///< before association
	Trajectory ref;				   ///< associated reference
	Trajectory est;				   ///< associated and aligned estimate (pose i ↔ ref pose i)
	std::vector<std::size_t> pose_ids;	///< per error: index into ref/est (RPE: the second pose j)
	std::vector<double> stamps;	   ///< per error: the estimate's stamp (RPE: of pose j), as evo
	std::vector<double> errors;	   ///< per error value, in `unit`
	Statistics stats;
};

/** "APE w.r.t. <relation> (<unit>)" — evo's metric name line. */
std::string ape_metric_title(PoseRelation r);
/** "RPE w.r.t. <relation> (<unit>)\nfor delta = <δ> (frames) using consecutive|all pairs". */
std::string rpe_metric_title(PoseRelation r, std::size_t delta, bool all_pairs);

/** APE as evo_ape: associate by stamps, align the estimate, per-pose errors, statistics. Throws
 * std::invalid_argument / std::runtime_error with a readable message on empty trajectories, no
 * matching stamps, or an impossible alignment. */
MetricResult compute_ape(const Trajectory& ref, const Trajectory& est, const ApeOptions& options = {});

/** RPE as evo_rpe with a delta in frames (pairs chosen after association). Needs at least δ+1
 * associated poses. */
MetricResult compute_rpe(const Trajectory& ref, const Trajectory& est, const RpeOptions& options = {});
}  // namespace swba::eval
