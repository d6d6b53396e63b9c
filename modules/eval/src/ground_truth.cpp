// Pairing of estimates with MRPT's ground-truth robot path (see ground_truth.h).
#include <swba/eval/evaluation.h>
#include <swba/eval/ground_truth.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace swba::eval
{
namespace
{
/** A TUM file: named *.tum, or its first data line has TUM's 8 columns (MRPT's path has 6). */
bool is_tum_file(const std::string& path)
{
	if (path.size() > 4 && path.compare(path.size() - 4, 4, ".tum") == 0) return true;
	std::error_code ec;
	if (!std::filesystem::is_regular_file(path, ec)) return false;  // the reader names what it is
	std::ifstream f(path);
	for (std::string line; std::getline(f, line);)
	{
		const auto b = line.find_first_not_of(" \t\r");
		if (b == std::string::npos || line[b] == '#' || line[b] == '%') continue;
		std::istringstream words(line);
		std::size_t n = 0;
		for (std::string w; words >> w;) n++;
		return n == 8;
	}
	return false;
}

/** The rawlog path without its .rawlog / .rawlog.gz ending. */
std::string rawlog_stem(const std::string& rawlog_path)
{
	std::string base = rawlog_path;
	for (const char* ext : {".rawlog.gz", ".rawlog"})
	{
		const std::string e = ext;
		if (base.size() > e.size() && base.compare(base.size() - e.size(), e.size(), e) == 0)
		{
			base.resize(base.size() - e.size());
			break;
		}
	}
	return base;
}
}  // namespace

std::string default_ground_truth_path(const std::string& rawlog_path)
{
	return rawlog_stem(rawlog_path) + "_ground_truth_robot_path.txt";
}

std::string default_landmarks_path(const std::string& rawlog_path)
{
	return rawlog_stem(rawlog_path) + "_ground_truth.txt";
}

std::vector<mrpt::poses::CPose3D> read_ground_truth_for(const std::string& path, std::size_t steps)
{
	// Row by row in both formats (row i = the pose at SF_i): a TUM file's stamps are not used for the
	// pairing (swba run's own gt.tum has t = row).
	const std::vector<mrpt::poses::CPose3D> rows = (is_tum_file(path) ? read_tum(path) : read_mrpt_ground_truth(path)).poses;
	if (rows.size() < steps + 1)
		throw std::runtime_error("ground truth '" + path + "': " + std::to_string(rows.size()) +
								 " rows, but the rawlog has " + std::to_string(steps) + " steps and needs " +
								 std::to_string(steps + 1) +
								 " rows (row i = true pose at SF_i; the estimate after step k pairs with row k+1)");
	return rows;
}

Trajectory ground_truth_trajectory(const std::vector<mrpt::poses::CPose3D>& rows)
{
	Trajectory t;
	for (std::size_t i = 0; i < rows.size(); i++) t.push_back(static_cast<double>(i), rows[i]);
	return t;
}

Trajectory paired_ground_truth(const std::vector<mrpt::poses::CPose3D>& rows, const Trajectory& estimate)
{
	Trajectory ref;
	for (std::size_t i = 0; i < estimate.size(); i++)
	{
		const double t = estimate.stamps[i];
		const double r = std::round(t);
		if (!(std::abs(t - r) < 1e-9) || r < 1)
			throw std::runtime_error("estimate pose " + std::to_string(i) + " has time " + std::to_string(t) +
									 ", not a step time k + 1 >= 1");
		const auto row = static_cast<std::size_t>(r);
		if (row >= rows.size())
			throw std::runtime_error("estimate at t = " + std::to_string(row) + " has no ground-truth row " +
									 std::to_string(row) + " (" + std::to_string(rows.size()) + " rows)");
		ref.push_back(t, rows[row]);
	}
	return ref;
}

std::vector<double> ape_errors_against_ground_truth(const std::vector<mrpt::poses::CPose3D>& rows,
													 const Trajectory& estimate, PoseRelation relation)
{
	return ape_errors(paired_ground_truth(rows, estimate), estimate, relation);
}

std::pair<Statistics, Statistics> ape_against_ground_truth(
	const std::vector<mrpt::poses::CPose3D>& rows, const Trajectory& estimate)
{
	return {compute_statistics(ape_errors_against_ground_truth(rows, estimate, PoseRelation::TranslationPart)),
			compute_statistics(ape_errors_against_ground_truth(rows, estimate, PoseRelation::FullTransformation))};
}
}  // namespace swba::eval
