/** \file directba_dataset.h
 * Reader of the course's direct-BA data set (share/data/directba/): images 0.png … N−1.png,
 * `poses.txt` (`t tx ty tz qx qy qz qw` per line, camera-from-world T_cw) and `points.txt`
 * (`x y z` + 16 patch intensities per line, world frame). Poses are returned as **world-from-camera**
 * (T_wc = T_cw⁻¹), the convention of swba::PhotometricPatchFactor and of TUM files.
 * Every error (missing or undecodable image, wrong column count, non-numeric token, zero quaternion)
 * throws std::runtime_error naming the file and the line. */
#pragma once

#include <swba/factors/photometric_patch.h>

#include <mrpt/poses/CPose3D.h>

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

namespace swba::io
{
/** A point of the data set: world position and its 4×4 host patch (sample order of
 * swba::PhotometricPatchFactor: k = 4·(dx+2) + (dy+2)). */
struct DirectBAPoint
{
	Eigen::Vector3d position = Eigen::Vector3d::Zero();
	PatchValues patch{};
};

struct DirectBADataset
{
	/** Timestamps as written in poses.txt (the course's file has them all equal to 1.46323e+09). */
	std::vector<double> timestamps;
	/** World-from-camera pose of image i. */
	std::vector<mrpt::poses::CPose3D> world_from_camera;
	std::vector<DirectBAPoint> points;
	/** Gray images (one per pose), shared so that factors can hold them. */
	std::vector<std::shared_ptr<const IntensityImage>> images;
	PatchCameraIntrinsics intrinsics;
};

/** The course's intrinsics (directBA.cpp): fx=277.34 fy=291.402 cx=312.234 cy=239.777. */
PatchCameraIntrinsics course_directba_intrinsics();

/** Loads an image with mrpt::img::CImage (PNG, JPEG, … as MRPT's build decodes them) and converts
 * it to gray (RGB → luminance; the course's PNGs have R = G = B, so gray = the stored value).
 * Throws std::runtime_error if the file is missing or cannot be decoded. */
IntensityImage load_intensity_image(const std::string& path);

/** Reads `t tx ty tz qx qy qz qw` lines (camera-from-world), returns T_wc per line; blank lines and
 * lines starting with '#' are skipped. The quaternion is normalised. */
void read_directba_poses(const std::string& path, std::vector<double>& timestamps,
						 std::vector<mrpt::poses::CPose3D>& world_from_camera);

/** Reads `x y z p0 … p15` lines (19 columns). */
std::vector<DirectBAPoint> read_directba_points(const std::string& path);

/** Reads a whole data set directory: poses.txt, points.txt and images 0.png … (N−1).png for the N
 * poses. `intrinsics` defaults to the course's. */
DirectBADataset read_directba_dataset(const std::string& dir,
									  const PatchCameraIntrinsics& intrinsics = course_directba_intrinsics());

/** Writes world-from-camera poses as a TUM trajectory (`t x y z qx qy qz qw`, single spaces,
 * 9 significant digits). Throws std::runtime_error if the file cannot be written. */
void write_directba_tum(const std::string& path, const std::vector<double>& timestamps,
						const std::vector<mrpt::poses::CPose3D>& world_from_camera);
}  // namespace swba::io
