/** \file directba_dataset.h
 * Reader of the direct-BA data set format (share/data/directba/): images 0.png … N−1.png,
 * `poses.txt` (`t tx ty tz qx qy qz qw` per line, camera-from-world T_cw) and `points.txt`
 * (`x y z` + 16 patch intensities per line, world frame). Poses are returned as **world-from-camera**
 * (T_wc = T_cw⁻¹), the convention of swba::PhotometricPatchFactor and of TUM files.
 * Every error (missing or undecodable image, wrong column count, non-numeric token, zero quaternion)
 * throws std::runtime_error naming the file and the line. */
#pragma once

#include <swba/core/image.h>

#include <mrpt/poses/CPose3D.h>

#include <Eigen/Core>
#include <array>
#include <memory>
#include <string>
#include <vector>

namespace swba::io
{
/** Number of intensities of a point's host patch in points.txt: 4×4 samples, sample k at the offset
 * (dx, dy) = (k / 4 − 2, k % 4 − 2) from the host pixel (the layout of swba::PhotometricPatchFactor). */
constexpr int kDirectBAPatchSize = 16;
using DirectBAPatch = std::array<double, kDirectBAPatchSize>;

/** A point of the data set: world position and its 4×4 host patch. */
struct DirectBAPoint
{
	Eigen::Vector3d position = Eigen::Vector3d::Zero();
	DirectBAPatch patch{};
};

struct DirectBADataset
{
	/** Timestamps as written in poses.txt (the shipped file has them all equal to 1.46323e+09). */
	std::vector<double> timestamps;
	/** World-from-camera pose of image i. */
	std::vector<mrpt::poses::CPose3D> world_from_camera;
	std::vector<DirectBAPoint> points;
	/** Gray images (one per pose), shared so that factors can hold them. */
	std::vector<std::shared_ptr<const IntensityImage>> images;
	PinholeIntrinsics intrinsics;
};

/** The intrinsics of the shipped data set: fx=277.34 fy=291.402 cx=312.234 cy=239.777. */
PinholeIntrinsics directba_dataset_intrinsics();

/** Loads an image with mrpt::img::CImage (PNG, JPEG, … as MRPT's build decodes them) and converts
 * it to gray (RGB → luminance; the shipped PNGs have R = G = B, so gray = the stored value).
 * Throws std::runtime_error if the file is missing or cannot be decoded, or if decoding it would take
 * more than image_memory_budget() of its size (see there). */
IntensityImage load_intensity_image(const std::string& path);

/** Reads `t tx ty tz qx qy qz qw` lines (camera-from-world), returns T_wc per line; blank lines and
 * lines starting with '#' are skipped. The quaternion is normalised. */
void read_directba_poses(const std::string& path, std::vector<double>& timestamps,
						 std::vector<mrpt::poses::CPose3D>& world_from_camera);

/** Reads `x y z p0 … p15` lines (19 columns). */
std::vector<DirectBAPoint> read_directba_points(const std::string& path);

/** Reads a whole data set directory: poses.txt, points.txt and images 0.png … (N−1).png for the N
 * poses. `intrinsics` defaults to the shipped data set's. */
/** Memory an image file of `file_bytes` bytes may take to decode: 256 MiB + 64 × file_bytes. Real
 * photographs compress a few times; a PNG declaring more pixels than this is refused before decoding
 * (a few hundred kilobytes of zeros can declare gigabytes), and other formats decode under this
 * budget (swba::ScopedMemoryBudget). */
std::uint64_t image_memory_budget(std::uint64_t file_bytes);

DirectBADataset read_directba_dataset(const std::string& dir,
									  const PinholeIntrinsics& intrinsics = directba_dataset_intrinsics());

}  // namespace swba::io
