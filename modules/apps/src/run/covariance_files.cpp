#include "covariance_files.h"

#include <cstdio>
#include <sstream>

namespace swba::apps
{
namespace
{
/** The upper triangle of `m` row by row, each entry with a leading space. */
template <class M>
void upper_triangle(std::ostringstream& s, const M& m)
{
	char buf[32];
	for (Eigen::Index i = 0; i < m.rows(); i++)
		for (Eigen::Index j = i; j < m.cols(); j++)
		{
			std::snprintf(buf, sizeof(buf), " %.9e", m(i, j));
			s << buf;
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
	std::ostringstream s;
	char buf[64];
	for (std::size_t i = 0; i < row.covariance.size() && i < row.estimate.size(); i++)
	{
		const estimators::PoseCovariance& c = row.covariance[i];
		const Eigen::Matrix3d position = world_position_covariance(row.estimate.poses[i], c);
		std::snprintf(buf, sizeof(buf), "%.9f", row.estimate.stamps[i]);  // as the TUM file
		s << buf;
		upper_triangle(s, position);
		upper_triangle(s, c);
		s << "\n";
	}
	return s.str();
}

std::string format_landmark_covariances(const RunRow& row)
{
	std::ostringstream s;
	char buf[96];
	for (const auto& [id, l] : row.landmarks)
	{
		std::snprintf(buf, sizeof(buf), "%d %.9f %.9f %.9f", static_cast<int>(id), l.position.x(), l.position.y(),
					  l.position.z());
		s << buf;
		upper_triangle(s, l.covariance);
		s << "\n";
	}
	return s.str();
}

std::pair<std::string, std::string> covariance_file_names(const std::string& tum_file)
{
	const std::string stem = tum_file.size() > 4 && tum_file.compare(tum_file.size() - 4, 4, ".tum") == 0
								 ? tum_file.substr(0, tum_file.size() - 4)
								 : tum_file;
	return {stem + ".cov", stem + "_landmarks.cov"};
}
}  // namespace swba::apps
