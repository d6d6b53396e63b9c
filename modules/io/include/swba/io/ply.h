/** \file ply.h
 * ASCII PLY point clouds with per-vertex colour (camera centres green, points white in
 * `swba directba`). Readable by MeshLab, CloudCompare, Open3D. */
#pragma once

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

namespace swba::io
{
struct ColoredPoint
{
	Eigen::Vector3d p;
	std::array<unsigned char, 3> rgb{255, 255, 255};
};

/** Writes `points` as an ASCII PLY (x y z red green blue). Throws std::runtime_error with the path
 * if the file cannot be written. */
void write_ply(const std::string& path, const std::vector<ColoredPoint>& points);

/** Convenience: camera centres in green (0,255,0) followed by points in white. */
void write_ply(const std::string& path, const std::vector<Eigen::Vector3d>& camera_centres,
			   const std::vector<Eigen::Vector3d>& points);
}  // namespace swba::io
