// Shared helpers of the window tests: the default rawlog, its ground truth and APE.
#pragma once

#include <swba/estimators/sliding_window.h>
#include <swba/eval/evaluation.h>
#include <swba/eval/trajectory.h>
#include <swba/io/rawlog.h>

#include <map>
#include <string>

namespace swba::test
{
inline std::string dataset(const std::string& name) { return std::string(SWBA_MRPT_DATASETS) + "/" + name; }

/** An mrpt-common rawlog, read once per test binary. */
inline const io::Rawlog& cached_rawlog(const std::string& name)
{
	static std::map<std::string, io::Rawlog> cache;
	auto it = cache.find(name);
	if (it == cache.end()) it = cache.emplace(name, io::read_rawlog(dataset(name))).first;
	return it->second;
}

/** kf-slam_6D_demo, read once. */
inline const io::Rawlog& demo_rawlog() { return cached_rawlog("kf-slam_6D_demo.rawlog"); }

inline eval::Trajectory ground_truth(const std::string& path)
{
	return eval::read_mrpt_ground_truth(path);  // row i has t = i
}

inline double ape_trans_rmse(const eval::Trajectory& gt, const eval::Trajectory& est)
{
	return eval::compute_ape(gt, est).stats.rmse;
}
}  // namespace swba::test
