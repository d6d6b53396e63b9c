/** \file association_quality.h
 * How well an estimator associated readings to landmarks, against the truth: the simulator's landmark
 * IDs when the rawlog has them, else the true landmark nearest to what each reading measures from the
 * true pose (mrpt-common's / simul-landmarks' `<rawlog stem>_ground_truth.txt`). */
#pragma once

#include <swba/io/rawlog.h>

#include <mrpt/poses/CPose3D.h>

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace swba::estimators
{
/** Readings by step: ids[k][i] is a landmark ID for reading i of step k (−1: none). */
using ReadingIds = std::vector<std::vector<std::int32_t>>;

/** Counts of evaluate_association(). An estimated landmark is *confirmed* when two or more readings
 * were given its ID; it *stands for* the true landmark most of its readings come from (ties: the
 * smallest ID). Of the confirmed landmarks standing for one true landmark, the one with the most
 * readings (ties: the smallest ID) is its *primary*; the others are duplicates. */
struct AssociationQuality
{
	std::size_t readings = 0;      ///< readings with a true landmark
	std::size_t associated = 0;    ///< of these, given the ID of a confirmed landmark
	std::size_t correct = 0;       ///< of these, given the ID of the primary of their own true landmark
	std::size_t landmarks = 0;     ///< confirmed estimated landmarks
	std::size_t duplicates = 0;    ///< confirmed landmarks that are not the primary of the landmark they stand for
	/** Confirmed landmarks fewer than half of whose readings come from the landmark they stand for. */
	std::size_t spurious = 0;
	std::size_t true_landmarks = 0;  ///< distinct true landmarks seen
	/** correct / associated (1 when nothing was associated). */
	double fraction_correct() const
	{
		return associated ? static_cast<double>(correct) / static_cast<double>(associated) : 1.0;
	}
};

/** Compares `assigned` with `truth` (same shape; a step or reading missing from `assigned` counts as
 * not associated). */
AssociationQuality evaluate_association(const ReadingIds& assigned, const ReadingIds& truth);

/** The readings' own landmark IDs (−1 where the sensor reported none). */
ReadingIds reading_ids(const io::Rawlog& rawlog);

/** True landmark positions by ID from a simulator ground-truth file: one landmark per line, x y z
 * first and the ID last (mrpt-common's and simul-landmarks' `*_ground_truth.txt`). Throws
 * std::runtime_error naming the file and line on a missing file or a malformed line. */
std::map<std::int32_t, Eigen::Vector3d> read_landmark_ground_truth(const std::string& path);

/** The true landmark of each reading: the one nearest to the point the reading measures from the true
 * robot pose `robot_path[k + 1]` of step k (robot_path[0] = the initial pose) and the step's sensor
 * pose, if within `max_distance` metres (else −1). Steps beyond the path get −1. */
ReadingIds true_landmarks_of_readings(const io::Rawlog& rawlog, const std::vector<mrpt::poses::CPose3D>& robot_path,
									  const std::map<std::int32_t, Eigen::Vector3d>& landmarks, double max_distance);
}  // namespace swba::estimators
