/** \file trajectory.h
 * Time-stamped 3-D trajectories and their file formats: TUM (`t x y z qx qy qz qw`) and MRPT's
 * ground-truth robot-path files (`x y z yaw pitch roll`, one row per step). */
#pragma once

#include <swba/core/names.h>

#include <array>

#include <mrpt/poses/CPose3D.h>

#include <Eigen/Core>
#include <cstddef>
#include <iosfwd>
#include <stdexcept>
#include <string>
#include <vector>

namespace swba::eval
{
/** A trajectory: stamps[i] (seconds, or step index) is the time of poses[i] (body → world). */
struct Trajectory
{
	std::vector<double> stamps;
	std::vector<mrpt::poses::CPose3D> poses;

	std::size_t size() const { return poses.size(); }
	bool empty() const { return poses.empty(); }
	void push_back(double t, const mrpt::poses::CPose3D& p)
	{
		stamps.push_back(t);
		poses.push_back(p);
	}
	/** Positions as a 3×N matrix (column i = translation of poses[i]). */
	Eigen::Matrix3Xd positions() const;
	/** The sub-trajectory made of the rows `ids` (in that order, repetitions allowed). */
	Trajectory subset(const std::vector<std::size_t>& ids) const;
};

/** A malformed trajectory file: what() is "<file>:<line>: <message>" (line 0: the whole file). */
struct TrajectoryFileError : std::runtime_error
{
	TrajectoryFileError(std::string file, std::size_t line, const std::string& message);
	std::string file;
	std::size_t line = 0;
};

/** Options for reading TUM files. */
struct TumReadOptions
{
	/** A quaternion whose norm differs from 1 by at most this is normalised silently (text files with
	 * 6–9 decimals are off by ~1e-9..1e-6); a larger deviation, a zero quaternion, is an error.
	 * (Default = 1e-3) */
	double quaternion_norm_tolerance = 1e-3;
};

/** Reads a TUM trajectory file: one pose per row `t x y z qx qy qz qw` (whitespace-separated), `#`
 * starts a comment line, blank lines are skipped. Rows must have exactly 8 finite numbers, stamps
 * must not decrease (equal stamps are kept). An empty file gives an empty trajectory. Throws
 * TrajectoryFileError naming file and line (also when the file cannot be opened). */
Trajectory read_tum(const std::string& path, const TumReadOptions& options = {});
/** As read_tum(path), from a stream; `source_name` is used in error messages. */
Trajectory read_tum(std::istream& in, const std::string& source_name, const TumReadOptions& options = {});

/** Writes `t x y z qx qy qz qw` rows, single spaces, `decimals` digits after the point (Default = 9),
 * quaternion with qw ≥ 0. Throws std::runtime_error naming the path if it cannot be written. */
void write_tum(const std::string& path, const Trajectory& trajectory, int decimals = 9);
void write_tum(std::ostream& out, const Trajectory& trajectory, int decimals = 9);

/** Reads an MRPT ground-truth robot-path file (e.g. kf-slam_6D_demo_ground_truth_robot_path.txt):
 * `%` comment lines, then rows `x y z yaw pitch roll` (metres, radians); the i-th data row gets
 * t = i (the step index, see doc/evaluation.md). Throws TrajectoryFileError with file:line on a
 * wrong column count or a non-numeric / non-finite value. */
Trajectory read_mrpt_ground_truth(const std::string& path);
Trajectory read_mrpt_ground_truth(std::istream& in, const std::string& source_name);

/** Text formats of a trajectory file. */
enum class TrajectoryFormat
{
	Tum,	   ///< "tum": `t x y z qx qy qz qw` per row (read_tum)
	MrptGt	   ///< "mrpt-gt": MRPT ground-truth robot path, `x y z yaw pitch roll` per row, row i at t = i
};
constexpr std::array<EnumName<TrajectoryFormat>, 2> enum_names(TrajectoryFormat)
{
	return {{{TrajectoryFormat::Tum, "tum"}, {TrajectoryFormat::MrptGt, "mrpt-gt"}}};
}

/** Reads a trajectory file in `format` (read_tum or read_mrpt_ground_truth). Throws
 * TrajectoryFileError on a malformed file. */
Trajectory read_trajectory(const std::string& path, TrajectoryFormat format = TrajectoryFormat::Tum);
}  // namespace swba::eval
