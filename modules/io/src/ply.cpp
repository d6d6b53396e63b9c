#include <swba/io/ply.h>

#include <swba/core/file.h>

#include <cstdio>
#include <fstream>
#include <stdexcept>

namespace swba::io
{
void write_ply(const std::string& path, const std::vector<ColoredPoint>& points)
{
	write_file_atomically(path, [&](std::ostream& f) {
		f << "ply\nformat ascii 1.0\nelement vertex " << points.size()
		  << "\nproperty float x\nproperty float y\nproperty float z\n"
			 "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n";
		char buf[160];
		for (const auto& cp : points)
		{
			std::snprintf(buf, sizeof(buf), "%.9g %.9g %.9g %d %d %d\n", cp.p.x(), cp.p.y(), cp.p.z(),
						  cp.rgb[0], cp.rgb[1], cp.rgb[2]);
			f << buf;
		}
	});
}

void write_ply(const std::string& path, const std::vector<Eigen::Vector3d>& camera_centres,
			   const std::vector<Eigen::Vector3d>& points)
{
	std::vector<ColoredPoint> all;
	all.reserve(camera_centres.size() + points.size());
	for (const auto& c : camera_centres) all.push_back({c, {0, 255, 0}});
	for (const auto& p : points) all.push_back({p, {255, 255, 255}});
	write_ply(path, all);
}
}  // namespace swba::io
