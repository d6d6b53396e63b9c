// Trajectories and their text formats (TUM, MRPT ground-truth robot paths).
#include "swba/eval/trajectory.h"
#include "swba/eval/text_format.h"
#include "data_lines.h"
#include <swba/core/file.h>

#include <stdexcept>
#include <mrpt/math/CQuaternion.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace swba::eval
{
Eigen::Matrix3Xd Trajectory::positions() const
{
	Eigen::Matrix3Xd p(3, static_cast<Eigen::Index>(poses.size()));
	for (std::size_t i = 0; i < poses.size(); i++)
		p.col(static_cast<Eigen::Index>(i)) << poses[i].x(), poses[i].y(), poses[i].z();
	return p;
}

Trajectory Trajectory::subset(const std::vector<std::size_t>& ids) const
{
	Trajectory out;
	out.stamps.reserve(ids.size());
	out.poses.reserve(ids.size());
	for (std::size_t i : ids) out.push_back(stamps.at(i), poses.at(i));
	return out;
}

TrajectoryFileError::TrajectoryFileError(std::string file_, std::size_t line_, const std::string& message)
	: std::runtime_error(file_ + (line_ ? ":" + std::to_string(line_) : std::string()) + ": " + message),
	  file(std::move(file_)),
	  line(line_)
{
}

namespace
{
/** Splits a data line into whitespace-separated tokens. */
std::vector<std::string> split_tokens(const std::string& line)
{
	std::vector<std::string> tokens;
	std::istringstream ss(line);
	std::string tok;
	while (ss >> tok) tokens.push_back(tok);
	return tokens;
}

/** Parses one row of exactly `names.size()` finite numbers or throws with file:line. */
std::vector<double> parse_row(const std::string& line, const std::vector<const char*>& names,
							  const std::string& source, std::size_t line_no, const char* format)
{
	const auto tokens = split_tokens(line);
	if (tokens.size() != names.size())
		throw TrajectoryFileError(source, line_no,
								  "expected " + std::to_string(names.size()) + " columns (" + format +
									  "), found " + std::to_string(tokens.size()));
	std::vector<double> v(tokens.size());
	for (std::size_t k = 0; k < tokens.size(); k++)
	{
		const char* s = tokens[k].c_str();
		char* end = nullptr;
		errno = 0;
		v[k] = std::strtod(s, &end);
		if (end == s || *end != '\0')
			throw TrajectoryFileError(source, line_no,
									  std::string("column ") + std::to_string(k + 1) + " (" + names[k] +
										  ") is not a number: '" + tokens[k] + "'");
		if (!std::isfinite(v[k]))
			throw TrajectoryFileError(source, line_no,
									  std::string("column ") + std::to_string(k + 1) + " (" + names[k] +
										  ") is not finite: '" + tokens[k] + "'");
	}
	return v;
}

/** Opens `path` for reading or throws TrajectoryFileError naming it. */
std::ifstream open_input(const std::string& path)
{
	std::error_code ec;
	const auto st = std::filesystem::status(path, ec);
	if (st.type() == std::filesystem::file_type::directory) throw TrajectoryFileError(path, 0, "is a directory, not a file");
	if (st.type() != std::filesystem::file_type::regular && st.type() != std::filesystem::file_type::not_found)
		throw TrajectoryFileError(path, 0, "is not a regular file (a FIFO, device or socket)");
	std::ifstream f(path, std::ios::in | std::ios::binary);
	if (!f) throw TrajectoryFileError(path, 0, "cannot open file");
	if (const std::string note = binary_data_note(f); !note.empty()) throw TrajectoryFileError(path, 0, note);
	return f;
}

}  // namespace

Trajectory read_tum(std::istream& in, const std::string& source, const TumReadOptions& options)
{
	static const std::vector<const char*> names = {"t", "x", "y", "z", "qx", "qy", "qz", "qw"};
	Trajectory traj;
	std::size_t prev_line = 0;
	detail::for_each_data_line(in, source, '#', [&](const std::string& line, std::size_t line_no) {
		const auto first = line.find_first_not_of(" \t");
		if (traj.empty() && first != std::string::npos && line[first] == '%')
			throw TrajectoryFileError(source, line_no,
									  "'%' starts a comment in MRPT's files, not in TUM's: an MRPT ground-truth path? "
									  "(swba ape: --ref-format mrpt-gt)");
		const auto v = parse_row(line, names, source, line_no, "t x y z qx qy qz qw");
		if (!traj.empty() && v[0] < traj.stamps.back())
			throw TrajectoryFileError(source, line_no,
									  "time stamp " + format_significant(v[0], 10) + " is before the previous one (" +
										  format_significant(traj.stamps.back(), 10) + " on line " + std::to_string(prev_line) +
										  "): stamps must not decrease");
		const double qx = v[4], qy = v[5], qz = v[6], qw = v[7];
		const double norm = std::sqrt(qx * qx + qy * qy + qz * qz + qw * qw);
		if (norm == 0.0) throw TrajectoryFileError(source, line_no, "zero quaternion (qx qy qz qw all 0)");
		if (std::abs(norm - 1.0) > options.quaternion_norm_tolerance)
			throw TrajectoryFileError(source, line_no,
									  "quaternion is not unit: norm " + format_significant(norm, 10) + " (tolerance " +
										  format_significant(options.quaternion_norm_tolerance, 10) + ")");
		const mrpt::math::CQuaternionDouble q(qw / norm, qx / norm, qy / norm, qz / norm);
		traj.push_back(v[0], mrpt::poses::CPose3D(q, v[1], v[2], v[3]));
		prev_line = line_no;
	});
	return traj;
}

Trajectory read_tum(const std::string& path, const TumReadOptions& options)
{
	std::ifstream f = open_input(path);
	return read_tum(f, path, options);
}

void write_tum(std::ostream& out, const Trajectory& trajectory, int decimals)
{
	if (trajectory.stamps.size() != trajectory.poses.size())
		throw std::invalid_argument("write_tum: stamps and poses differ in size");
	std::string line;
	for (std::size_t i = 0; i < trajectory.size(); i++)
	{
		const auto& p = trajectory.poses[i];
		mrpt::math::CQuaternionDouble q;
		p.getAsQuaternion(q);
		const double sgn = q.r() < 0 ? -1.0 : 1.0;
		line.clear();
		for (double v : {trajectory.stamps[i], p.x(), p.y(), p.z(), sgn * q.x(), sgn * q.y(), sgn * q.z(), sgn * q.r()})
		{
			if (!line.empty()) line += ' ';
			append_fixed(line, v, decimals);
		}
		line += '\n';
		out << line;
	}
}

void write_tum(const std::string& path, const Trajectory& trajectory, int decimals)
{
	write_file_atomically(path, [&](std::ostream& f) { write_tum(f, trajectory, decimals); });
}

Trajectory read_mrpt_ground_truth(std::istream& in, const std::string& source)
{
	static const std::vector<const char*> names = {"x", "y", "z", "yaw", "pitch", "roll"};
	Trajectory traj;
	detail::for_each_data_line(in, source, '%', [&](const std::string& line, std::size_t line_no) {
		const auto v = parse_row(line, names, source, line_no, "x y z yaw pitch roll");
		traj.push_back(static_cast<double>(traj.size()), mrpt::poses::CPose3D(v[0], v[1], v[2], v[3], v[4], v[5]));
	});
	return traj;
}

Trajectory read_mrpt_ground_truth(const std::string& path)
{
	std::ifstream f = open_input(path);
	return read_mrpt_ground_truth(f, path);
}

Trajectory read_trajectory(const std::string& path, TrajectoryFormat format)
{
	return format == TrajectoryFormat::MrptGt ? read_mrpt_ground_truth(path) : read_tum(path);
}
}  // namespace swba::eval
