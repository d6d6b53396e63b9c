// swba run: the covariance files beside each TUM file (doc/formats.md, "Covariance files").
#pragma once

#include <swba/apps/run.h>

#include <string>

namespace swba::apps
{
/** The world-frame position covariance R Σ_ρρ Rᵀ of `pose` from its tangent covariance (T_true = T·Exp(δ),
 * δ = [ρ, ω]: ρ is in the pose's frame). */
Eigen::Matrix3d world_position_covariance(const mrpt::poses::CPose3D& pose, const estimators::PoseCovariance& covariance);
/** `<stem>.cov`: one line per pose of row.estimate (the TUM file's rows): the stamp, the 6 upper-triangle
 * entries (xx xy xz yy yz zz) of the world-frame position covariance R Σ_ρρ Rᵀ, then the 21
 * upper-triangle entries (row-major) of the 6×6 pose covariance in the tangent convention. */
std::string format_pose_covariances(const RunRow& row);
/** `<stem>_landmarks.cov`: one line per landmark by ID: the ID, x y z, the 6 upper-triangle entries of
 * its position covariance. */
std::string format_landmark_covariances(const RunRow& row);
/** The covariance file names of a TUM file name: "<stem>.cov" and "<stem>_landmarks.cov". */
std::pair<std::string, std::string> covariance_file_names(const std::string& tum_file);
}  // namespace swba::apps
