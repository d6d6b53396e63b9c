// Shared helpers of the window tests: the default rawlog, its ground truth and APE.
#pragma once

#include <swba/estimators/sliding_window.h>
#include <swba/eval/evaluation.h>
#include <swba/io/rawlog.h>

#include <string>

namespace swba::test
{
inline std::string dataset(const std::string& name) { return std::string(SWBA_MRPT_DATASETS) + "/" + name; }

inline eval::Trajectory ground_truth(const std::string& path)
{
	const auto poses = io::read_ground_truth_path(path);
	eval::Trajectory t;
	for (std::size_t i = 0; i < poses.size(); i++) t.push_back(static_cast<double>(i), poses[i]);
	return t;
}

inline double ape_trans_rmse(const eval::Trajectory& gt, const eval::Trajectory& est)
{
	return eval::compute_ape(gt, est).stats.rmse;
}
}  // namespace swba::test
