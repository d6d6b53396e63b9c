// APE/RPE pose relations and statistics with evo's definitions.
#include "swba/eval/metrics.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "swba/eval/alignment.h"

namespace swba::eval
{
PoseRelation parse_pose_relation(const std::string& name) { return parse_enum<PoseRelation>(name, "pose relation"); }

std::string pose_relation_name(PoseRelation r) { return enum_name(r); }

std::string pose_relation_description(PoseRelation r)
{
	switch (r)
	{
		case PoseRelation::TranslationPart: return "translation part";
		case PoseRelation::FullTransformation: return "full transformation";
		case PoseRelation::RotationPart: return "rotation part";
		case PoseRelation::RotationAngleDeg:
		case PoseRelation::RotationAngleRad: return "rotation angle";
	}
	return "?";
}

std::string pose_relation_unit(PoseRelation r)
{
	switch (r)
	{
		case PoseRelation::TranslationPart: return "m";
		case PoseRelation::FullTransformation:
		case PoseRelation::RotationPart: return "unit-less";
		case PoseRelation::RotationAngleDeg: return "deg";
		case PoseRelation::RotationAngleRad: return "rad";
	}
	return "?";
}

double rotation_angle(const Eigen::Matrix3d& R)
{
	const Eigen::Vector3d w(R(2, 1) - R(1, 2), R(0, 2) - R(2, 0), R(1, 0) - R(0, 1));
	const double sin_angle = 0.5 * w.norm();
	const double cos_angle = 0.5 * (R.trace() - 1.0);
	return std::atan2(sin_angle, cos_angle);
}

namespace
{
constexpr double kPi = 3.14159265358979323846;

/** inv(A)·B for rigid transforms (A's rotation block orthonormal). */
Eigen::Matrix4d relative(const Eigen::Matrix4d& A, const Eigen::Matrix4d& B)
{
	Eigen::Matrix4d Ainv = Eigen::Matrix4d::Identity();
	Ainv.topLeftCorner<3, 3>() = A.topLeftCorner<3, 3>().transpose();
	Ainv.topRightCorner<3, 1>() = -A.topLeftCorner<3, 3>().transpose() * A.topRightCorner<3, 1>();
	return Ainv * B;
}

void check_associated(const Trajectory& ref, const Trajectory& est, const char* what)
{
	if (ref.size() != est.size())
		throw std::invalid_argument(std::string(what) + ": trajectories must be associated (same number of poses; " +
									std::to_string(ref.size()) + " vs " + std::to_string(est.size()) + ")");
}
}  // namespace

double pose_error(const Eigen::Matrix4d& E, PoseRelation r)
{
	switch (r)
	{
		case PoseRelation::TranslationPart: return E.topRightCorner<3, 1>().norm();
		case PoseRelation::FullTransformation: return (E - Eigen::Matrix4d::Identity()).norm();
		case PoseRelation::RotationPart:
			return (E.topLeftCorner<3, 3>() - Eigen::Matrix3d::Identity()).norm();
		case PoseRelation::RotationAngleRad: return std::abs(rotation_angle(E.topLeftCorner<3, 3>()));
		case PoseRelation::RotationAngleDeg:
			return std::abs(rotation_angle(E.topLeftCorner<3, 3>())) * (180.0 / kPi);
	}
	return 0.0;
}

std::vector<double> ape_errors(const Trajectory& ref, const Trajectory& est, PoseRelation r)
{
	check_associated(ref, est, "APE");
	std::vector<double> e(ref.size());
	for (std::size_t i = 0; i < ref.size(); i++)
	{
		if (r == PoseRelation::TranslationPart)
		{
			// As evo: the distance of the positions (no matrix products).
			const double dx = est.poses[i].x() - ref.poses[i].x();
			const double dy = est.poses[i].y() - ref.poses[i].y();
			const double dz = est.poses[i].z() - ref.poses[i].z();
			e[i] = std::sqrt(dx * dx + dy * dy + dz * dz);
		}
		else
			e[i] = pose_error(relative(to_matrix(est.poses[i]), to_matrix(ref.poses[i])), r);
	}
	return e;
}

std::vector<std::pair<std::size_t, std::size_t>> rpe_pairs(std::size_t num_poses, std::size_t delta, bool all_pairs)
{
	if (delta == 0) throw std::invalid_argument("RPE: delta must be at least 1 frame");
	std::vector<std::pair<std::size_t, std::size_t>> pairs;
	if (all_pairs)
		for (std::size_t i = 0; i + delta < num_poses; i++) pairs.emplace_back(i, i + delta);
	else
		for (std::size_t i = 0; i + delta < num_poses; i += delta) pairs.emplace_back(i, i + delta);
	return pairs;
}

std::vector<double> rpe_errors(const Trajectory& ref, const Trajectory& est, PoseRelation r,
							   const std::vector<std::pair<std::size_t, std::size_t>>& pairs)
{
	check_associated(ref, est, "RPE");
	std::vector<double> e;
	e.reserve(pairs.size());
	for (const auto& [i, j] : pairs)
	{
		const Eigen::Matrix4d Q_rel = relative(to_matrix(ref.poses.at(i)), to_matrix(ref.poses.at(j)));
		const Eigen::Matrix4d P_rel = relative(to_matrix(est.poses.at(i)), to_matrix(est.poses.at(j)));
		e.push_back(pose_error(relative(Q_rel, P_rel), r));
	}
	return e;
}

Statistics compute_statistics(const std::vector<double>& errors)
{
	if (errors.empty()) throw std::invalid_argument("statistics of an empty error vector (no pose pairs)");
	Statistics s;
	const std::size_t n = errors.size();
	s.count = n;
	double sum = 0, sse = 0;
	for (double e : errors)
	{
		sum += e;
		sse += e * e;
	}
	s.mean = sum / static_cast<double>(n);
	s.sse = sse;
	s.rmse = std::sqrt(sse / static_cast<double>(n));
	double var = 0;
	for (double e : errors) var += (e - s.mean) * (e - s.mean);
	s.std = std::sqrt(var / static_cast<double>(n));
	std::vector<double> sorted(errors);
	std::sort(sorted.begin(), sorted.end());
	s.min = sorted.front();
	s.max = sorted.back();
	s.median = (n % 2) ? sorted[n / 2] : 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]);
	return s;
}

std::vector<std::pair<std::string, double>> statistics_items(const Statistics& s)
{
	return {{"max", s.max}, {"mean", s.mean}, {"median", s.median}, {"min", s.min},
			{"rmse", s.rmse}, {"sse", s.sse},	{"std", s.std}};
}
}  // namespace swba::eval
