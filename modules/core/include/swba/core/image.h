/** \file image.h
 * Images as plain data: a single-channel float image and the pinhole intrinsics of the camera that
 * took it. Readers (swba::io) fill them; photometric factors (swba/factors/photometric_patch.h)
 * sample them. Pixel (col, row) has its centre at u = col, v = row. */
#pragma once

#include <cstddef>
#include <vector>

namespace swba
{
/** A single-channel image of float intensities (row-major, width × height). */
struct IntensityImage
{
	int width = 0;
	int height = 0;
	std::vector<float> pixels;  ///< pixels[row * width + col]

	IntensityImage() = default;
	IntensityImage(int w, int h, float fill = 0.f) : width(w), height(h), pixels(size_t(w) * size_t(h), fill) {}
	float at(int col, int row) const { return pixels[size_t(row) * size_t(width) + size_t(col)]; }
	float& at(int col, int row) { return pixels[size_t(row) * size_t(width) + size_t(col)]; }
	bool empty() const { return width <= 0 || height <= 0; }
};

/** Pinhole intrinsics (no distortion): u = fx·x/z + cx, v = fy·y/z + cy. */
struct PinholeIntrinsics
{
	double fx = 0, fy = 0, cx = 0, cy = 0;
};
}  // namespace swba
