// swba_cut_rawlog: a segment of a rawlog as a run of its own — steps FROM .. FROM + STEPS − 1 of an
// actions/sensory-frames rawlog (step k = action collection k and the sensory frame after it), with its
// ground truth expressed in the true pose before step FROM (row 0 of the new path is the identity, as
// the estimators start): OUT.rawlog, OUT_ground_truth_robot_path.txt and, when the input has one,
// OUT_ground_truth.txt (the landmarks). Odometry increments and readings are relative: copied as read.
// What for: more runs of a real log than it has starts (doc/benchmarks/realdata.md), each starting with
// an empty map at another place.
#include "../common/rawlog_tool.h"

#include <swba/estimators/association_quality.h>
#include <swba/eval/ground_truth.h>
#include <swba/eval/trajectory.h>

#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/obs/CSensoryFrame.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace
{
/** The segment's entries: an empty leading frame (the reader ignores a leading frame), then action
 * collection k and the frame after it for k in [from, from + steps). Throws when the rawlog is not
 * actions/frames pairs or is shorter than the segment. */
mrpt::obs::CRawlog cut(const mrpt::obs::CRawlog& in, std::size_t from, std::size_t steps)
{
	mrpt::obs::CRawlog out;
	out.insert(std::make_shared<mrpt::obs::CSensoryFrame>());
	std::size_t k = 0, kept = 0;
	for (std::size_t i = 0; i < in.size() && kept < steps; i++)
	{
		if (in.getType(i) != mrpt::obs::CRawlog::etActionCollection) continue;
		if (k++ < from) continue;
		if (i + 1 >= in.size() || in.getType(i + 1) != mrpt::obs::CRawlog::etSensoryFrame)
			throw std::runtime_error("action collection " + std::to_string(k - 1) + " is not followed by a sensory frame");
		out.insert(in.getAsAction(i));
		out.insert(in.getAsObservations(i + 1));
		kept++;
	}
	if (kept < steps)
		throw std::runtime_error("the rawlog has " + std::to_string(k) + " steps, fewer than " + std::to_string(from) +
								 " + " + std::to_string(steps));
	return out;
}

int run(int argc, char** argv)
{
	TCLAP::CmdLine cmd("A segment of a rawlog as a run of its own, its ground truth expressed in the true pose before "
					   "its first step.", ' ');
	TCLAP::UnlabeledValueArg<std::string> in("RAWLOG", "input rawlog (actions/sensory frames)", true, "", "RAWLOG", cmd);
	TCLAP::UnlabeledValueArg<std::string> out("OUT", "output stem: OUT.rawlog, OUT_ground_truth*.txt", true, "", "OUT", cmd);
	TCLAP::ValueArg<std::size_t> from("", "from", "first step (0-based) (Default: 0)", false, 0, "K", cmd);
	TCLAP::ValueArg<std::size_t> steps("", "steps", "steps in the segment, >= 1", true, 0, "N", cmd);
	TCLAP::ValueArg<std::string> gt("", "gt", "ground-truth robot path (Default: next to the rawlog)", false, "", "PATH", cmd);
	cmd.parse(argc, argv);
	if (steps.getValue() < 1) throw std::invalid_argument("--steps must be >= 1");
	const std::string gt_path = gt.getValue().empty() ? swba::eval::default_ground_truth_path(in.getValue()) : gt.getValue();
	const std::vector<mrpt::poses::CPose3D> path = swba::eval::read_mrpt_ground_truth(gt_path).poses;
	const std::size_t k0 = from.getValue(), n = steps.getValue();
	if (k0 + n >= path.size())
		throw std::runtime_error("ground truth '" + gt_path + "' has " + std::to_string(path.size()) + " rows, fewer than " +
								 std::to_string(k0 + n + 1));
	mrpt::obs::CRawlog rawlog;
	if (!rawlog.loadFromRawLogFile(in.getValue())) throw std::runtime_error("rawlog '" + in.getValue() + "': cannot be read");
	const std::string stem = out.getValue();
	if (!cut(rawlog, k0, n).saveToRawLogFile(stem + ".rawlog"))
		throw std::runtime_error("rawlog '" + stem + ".rawlog': cannot be written");
	const mrpt::poses::CPose3D origin = path[k0];
	std::ofstream g(stem + "_ground_truth_robot_path.txt");
	g << "% Columns are: x(m) y(m) z(m) yaw(rad) pitch(rad) roll(rad); rows " << k0 << ".." << k0 + n << " of " << gt_path
	  << " in the pose of row " << k0 << "\n";
	for (std::size_t j = k0; j <= k0 + n; j++)
	{
		const mrpt::poses::CPose3D p = path[j] - origin;
		char row[160];
		std::snprintf(row, sizeof row, "%.10f %.10f %.10f %.10f %.10f %.10f\n", p.x(), p.y(), p.z(), p.yaw(), p.pitch(), p.roll());
		g << row;
	}
	const std::string lm_path = swba::eval::default_landmarks_path(in.getValue());
	if (std::filesystem::exists(lm_path))
	{
		std::ofstream l(stem + "_ground_truth.txt");
		for (const auto& [id, x] : swba::estimators::read_landmark_ground_truth(lm_path))
		{
			const mrpt::math::TPoint3D q = origin.inverseComposePoint(mrpt::math::TPoint3D(x.x(), x.y(), x.z()));
			char row[160];
			std::snprintf(row, sizeof row, "%.6f %.6f %.6f %d\n", q.x, q.y, q.z, id);
			l << row;
		}
	}
	std::printf("cut_rawlog: steps %zu..%zu of %s -> %s.rawlog (ground truth in the pose of row %zu)\n", k0, k0 + n - 1,
				in.getValue().c_str(), stem.c_str(), k0);
	return 0;
}
}  // namespace

int main(int argc, char** argv) { return swba::bench::tool_main("cut_rawlog", argc, argv, run); }
