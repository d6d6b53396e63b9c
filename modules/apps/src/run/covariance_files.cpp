#include "covariance_files.h"

#include <swba/eval/text_format.h>

#include <string>

namespace swba::apps
{
namespace
{
/** The upper triangle of `m` row by row, each entry with a leading space. */
template <class M>
void upper_triangle(std::string& s, const M& m)
{
	for (Eigen::Index i = 0; i < m.rows(); i++)
		for (Eigen::Index j = i; j < m.cols(); j++)
		{
			s += ' ';
			eval::append_scientific(s, m(i, j), 9);
		}
}
}  // namespace

Eigen::Matrix3d world_position_covariance(const mrpt::poses::CPose3D& pose, const estimators::PoseCovariance& covariance)
{
	const Eigen::Matrix3d R = pose.getRotationMatrix().asEigen();
	return R * covariance.topLeftCorner<3, 3>() * R.transpose();
}

std::string format_pose_covariances(const RunRow& row)
{
	std::string s;
	for (std::size_t i = 0; i < row.covariance.size() && i < row.estimate.size(); i++)
	{
		const estimators::PoseCovariance& c = row.covariance[i];
		const Eigen::Matrix3d position = world_position_covariance(row.estimate.poses[i], c);
		eval::append_fixed(s, row.estimate.stamps[i], 9);  // as the TUM file
		upper_triangle(s, position);
		upper_triangle(s, c);
		s += '\n';
	}
	return s;
}

std::string format_landmark_covariances(const RunRow& row)
{
	std::string s;
	for (const auto& [id, l] : row.landmarks)
	{
		s += std::to_string(static_cast<int>(id));
		for (double v : {l.position.x(), l.position.y(), l.position.z()})
		{
			s += ' ';
			eval::append_fixed(s, v, 9);
		}
		upper_triangle(s, l.covariance);
		s += '\n';
	}
	return s;
}

std::pair<std::string, std::string> covariance_file_names(const std::string& tum_file)
{
	const std::string stem = tum_file.size() > 4 && tum_file.compare(tum_file.size() - 4, 4, ".tum") == 0
								 ? tum_file.substr(0, tum_file.size() - 4)
								 : tum_file;
	return {stem + ".cov", stem + "_landmarks.cov"};
}
}  // namespace swba::apps
