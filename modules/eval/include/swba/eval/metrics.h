/** \file metrics.h
 * Pose-error relations and statistics with evo's definitions (evo 1.36, metrics.py):
 * APE E_i = T_est,i⁻¹ · T_ref,i; RPE E_ij = (Q_i⁻¹ Q_j)⁻¹ (P_i⁻¹ P_j) with Q = reference, P = estimate. */
#pragma once

#include <swba/core/names.h>

#include <array>

#include <Eigen/Core>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "swba/eval/trajectory.h"

namespace swba::eval
{
/** What part of the error pose E is measured. */
enum class PoseRelation
{
	TranslationPart,	///< APE: ‖t_est − t_ref‖; RPE: ‖t(E)‖  (m)
	FullTransformation, ///< ‖E − I₄‖_F (unit-less)
	RotationPart,		///< ‖R(E) − I₃‖_F (unit-less)
	RotationAngleDeg,	///< |rotation vector of R(E)| in degrees
	RotationAngleRad	///< |rotation vector of R(E)| in radians
};

/** The command-line names; evo's `-r` names trans_part / rot_part are accepted too. */
constexpr std::array<EnumName<PoseRelation>, 7> enum_names(PoseRelation)
{
	return {{{PoseRelation::TranslationPart, "trans"}, {PoseRelation::FullTransformation, "full"}, {PoseRelation::RotationPart, "rot"},
			 {PoseRelation::RotationAngleDeg, "angle_deg"}, {PoseRelation::RotationAngleRad, "angle_rad"},
			 {PoseRelation::TranslationPart, "trans_part", true}, {PoseRelation::RotationPart, "rot_part", true}}};
}

/** Parses the command-line names "trans", "full", "rot", "angle_deg", "angle_rad" (evo's `-r` names
 * trans_part / rot_part are accepted too). Throws std::invalid_argument listing the valid names. */
PoseRelation parse_pose_relation(const std::string& name);
/** The command-line name ("trans", ...). */
std::string pose_relation_name(PoseRelation r);
/** evo's description: "translation part", "full transformation", "rotation part", "rotation angle". */
std::string pose_relation_description(PoseRelation r);
/** evo's unit: "m", "unit-less", "deg", "rad". */
std::string pose_relation_unit(PoseRelation r);

/** Rotation angle of a rotation matrix in [0, π], as atan2(‖vee(R − Rᵀ)‖/2, (tr R − 1)/2): accurate
 * near 0 and near π (no acos). */
double rotation_angle(const Eigen::Matrix3d& R);

/** The error value of relation `r` for an error pose E (4×4 homogeneous). */
double pose_error(const Eigen::Matrix4d& E, PoseRelation r);

/** APE per pose of associated trajectories (same length; pair i at index i). */
std::vector<double> ape_errors(const Trajectory& ref, const Trajectory& est, PoseRelation r);

/** Index pairs (i, j) for RPE with a delta in frames, as evo's filter_pairs_by_index:
 * consecutive pairs (0,δ), (δ,2δ), ... or, with all_pairs, (i, i+δ) for every i. */
std::vector<std::pair<std::size_t, std::size_t>> rpe_pairs(std::size_t num_poses, std::size_t delta, bool all_pairs);

/** RPE per pair of associated trajectories. */
std::vector<double> rpe_errors(const Trajectory& ref, const Trajectory& est, PoseRelation r,
							   const std::vector<std::pair<std::size_t, std::size_t>>& pairs);

/** evo's seven statistics of an error vector (std is the population std, ddof = 0; the median of an
 * even count is the mean of the two middle values). */
struct Statistics
{
	std::size_t count = 0;
	double max = 0, mean = 0, median = 0, min = 0, rmse = 0, sse = 0, std = 0;
};

/** Statistics of `errors`; throws std::invalid_argument if it is empty (evo would print NaNs). */
Statistics compute_statistics(const std::vector<double>& errors);

/** The statistics in evo's order (sorted by name): max, mean, median, min, rmse, sse, std. */
std::vector<std::pair<std::string, double>> statistics_items(const Statistics& s);
}  // namespace swba::eval
