/** \file report_helpers.h
 * Private helpers shared by the applications' reports (monoba, directba, run, nees). */
#pragma once

#include <mrpt/poses/CPose3D.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <ostream>
#include <string>

namespace swba::apps::detail
{
/** Rotation angle of R_aᵀ R_b in degrees (acos of the clamped trace: the figures the reports print). */
inline double rotation_angle_deg(const mrpt::poses::CPose3D& a, const mrpt::poses::CPose3D& b)
{
	const Eigen::Matrix3d E = a.getRotationMatrix().asEigen().transpose() * b.getRotationMatrix().asEigen();
	const double c = std::clamp((E.trace() - 1.0) * 0.5, -1.0, 1.0);
	return std::acos(c) * 180.0 / 3.14159265358979323846;
}
/** `v` with `decimals` digits after the point (the reports' fixed-point figures). */
inline std::string fixed(double v, int decimals)
{
	char buf[64];
	std::snprintf(buf, sizeof(buf), "%.*f", decimals, v);
	return buf;
}
/** Writes printf's `format` of the arguments to `os` (a report line: at most 511 characters). */
[[gnu::format(printf, 2, 3)]] inline void print_to(std::ostream& os, const char* format, ...)
{
	char buf[512];
	va_list args;
	va_start(args, format);
	std::vsnprintf(buf, sizeof(buf), format, args);
	va_end(args);
	os << buf;
}
/** `s` padded with spaces to width `w`, on the right / on the left (table columns). */
inline std::string pad_right(const std::string& s, std::size_t w) { return s.size() >= w ? s : s + std::string(w - s.size(), ' '); }
inline std::string pad_left(const std::string& s, std::size_t w) { return s.size() >= w ? s : std::string(w - s.size(), ' ') + s; }
/** "<program>: wrote N file(s) into DIR/" (one slash after DIR, however many it was given with). */
inline void print_wrote_files(std::ostream& log, const std::string& program, std::size_t n, std::string dir)
{
	while (dir.size() > 1 && dir.back() == '/') dir.pop_back();
	log << program << ": wrote " << n << (n == 1 ? " file" : " files") << " into " << dir << (dir == "/" ? "" : "/") << "\n";
}
}  // namespace swba::apps::detail
