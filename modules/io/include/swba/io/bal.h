/** \file bal.h
 * "Bundle Adjustment in the Large" (BAL, Agarwal et al. 2010) problems: reader and writer of the
 * text format. The problem they define (Snavely cameras, reprojection factors) is built by
 * swba/problems/bal.h.
 *
 * Format (whitespace separated):
 *   num_cameras num_points num_observations
 *   camera point x y                 (num_observations lines, one observation per line)
 *   9 numbers per camera             (ω Rodrigues(3), t(3), f, k1, k2; any line layout)
 *   3 numbers per point              (any line layout)
 * Observations are in pixels relative to the image centre; the Snavely model is described in
 * swba/factors/snavely_reprojection.h. */
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

namespace swba::io
{
struct BalObservation
{
	int camera = 0;
	int point = 0;
	double x = 0, y = 0;
};

/** A BAL problem in memory: parameters stored exactly as in the file. */
struct BalProblem
{
	static constexpr int kCameraParams = 9;
	static constexpr int kPointParams = 3;

	int num_cameras = 0;
	int num_points = 0;
	std::vector<BalObservation> observations;
	std::vector<double> cameras;  ///< kCameraParams per camera
	std::vector<double> points;   ///< kPointParams per point

	double* camera(int i) { return cameras.data() + kCameraParams * static_cast<size_t>(i); }
	const double* camera(int i) const { return cameras.data() + kCameraParams * static_cast<size_t>(i); }
	double* point(int j) { return points.data() + kPointParams * static_cast<size_t>(j); }
	const double* point(int j) const { return points.data() + kPointParams * static_cast<size_t>(j); }
};

/** Malformed BAL input: what() is "<source>:<line>: <reason>"; line() is 1-based. */
class BalParseError : public std::runtime_error
{
   public:
	BalParseError(const std::string& source, int line, const std::string& reason);
	int line() const { return line_; }

   private:
	int line_;
};

/** True when this build reads bzip2-compressed files (libbz2 linked into swba::io). */
bool bal_bzip2_supported();

/** Reads a BAL file; bzip2-compressed content ("BZh" magic) is decompressed when
 * bal_bzip2_supported(). Throws std::runtime_error if the file cannot be read and BalParseError
 * (with the line) on a truncated file, a header/count mismatch, an out-of-range camera or point
 * index, a non-numeric or non-finite number. Points behind their cameras are accepted. */
BalProblem read_bal(const std::string& path);

/** Parses BAL text; `source` names it in error messages. */
BalProblem parse_bal(const std::string& text, const std::string& source = "<bal>");

/** Writes `problem` in the BAL format (numbers with 17 significant digits, so that reading the file
 * back gives the same doubles). Throws std::runtime_error if the file cannot be written. */
void write_bal(const std::string& path, const BalProblem& problem);
}  // namespace swba::io
