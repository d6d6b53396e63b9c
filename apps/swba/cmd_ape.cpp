// swba ape / swba rpe: absolute and relative pose error of a trajectory against a reference, as evo.
#include <swba/apps/trajectory_metric.h>
#include <swba/eval/metrics.h>

#include <cmath>
#include <iostream>
#include <string>
#include <vector>

#include "cli.h"
#include "command.h"

namespace swba::app
{
namespace
{
/** The command line shared by `swba ape` and `swba rpe` (RPE adds --delta and --all-pairs). */
struct MetricCommandLine
{
	const bool relative;
	TCLAP::CmdLine cmd;
	TCLAP::UnlabeledValueArg<std::string> ref_arg{"REF", "reference trajectory file (TUM: t x y z qx qy qz qw)", true, "",
												  "REF"};
	TCLAP::UnlabeledValueArg<std::string> est_arg{"EST", "estimated trajectory file (TUM)", true, "", "EST"};
	std::vector<std::string> relations = {"trans", "full", "rot", "angle_deg", "angle_rad"};
	TCLAP::ValuesConstraint<std::string> relation_values{relations};
	TCLAP::ValueArg<std::string> relation_arg{
		"r", "pose-relation",
		"pose relation measured: trans = translation part (m), full = full transformation ||E - I||_F "
		"(unit-less), rot = rotation part ||R(E) - I||_F (unit-less), angle_deg / angle_rad = rotation angle "
		"of E (Default: trans)",
		false, "trans", &relation_values};
	TCLAP::SwitchArg align_arg{"a", "align", "align the estimate to the reference with Umeyama's method: SE(3), "
									 "or Sim(3) together with -s"};
	TCLAP::SwitchArg scale_arg{"s", "correct-scale",
							   "correct the scale (Umeyama Sim(3) scale); alone: scale only, no rotation/translation"};
	TCLAP::SwitchArg origin_arg{"", "align-origin",
								"align the first estimated pose to the first reference pose (after -a/-s if given)"};
	TCLAP::ValueArg<double> max_diff_arg{"", "t-max-diff",
										 "largest time difference (s) for associating poses by stamp (Default: 0.01)",
										 false, 0.01, "S"};
	TCLAP::ValueArg<double> offset_arg{"", "t-offset", "time offset (s) added to the estimate's stamps (Default: 0)",
									   false, 0.0, "S"};
	std::vector<std::string> formats = {"tum", "mrpt-gt"};
	TCLAP::ValuesConstraint<std::string> format_values{formats};
	TCLAP::ValueArg<std::string> ref_format_arg{
		"", "ref-format",
		"format of REF: tum, or mrpt-gt = MRPT ground-truth robot path (x y z yaw pitch roll per row, row i at "
		"t = i) (Default: tum)",
		false, "tum", &format_values};
	TCLAP::ValueArg<std::string> save_arg{
		"", "save-results",
		"write <m>_stats.json, <m>_stats.csv, <m>_errors.csv (per pose), <m>_result.json and <m>_est_aligned.tum "
		"into DIR (m = ape or rpe; DIR is created) (Default: not written)",
		false, "", "DIR"};
	TCLAP::ValueArg<std::string> plot_arg{
		"", "plot",
		"write plots into DIR: <m>_trajectories (top view) and <m>_errors (error over time), as .png and .svg "
		"when gnuplot is on PATH (else a one-line note), plus their .dat/.gp sources (Default: not written)",
		false, "", "DIR"};
	TCLAP::ValueArg<int> delta_arg{"", "delta", "RPE: frames between the two poses of a pair (Default: 1)", false, 1,
								   "N"};
	TCLAP::SwitchArg all_pairs_arg{"", "all-pairs", "RPE: use every pair (i, i+delta), not only consecutive ones"};

	explicit MetricCommandLine(bool is_relative) : relative(is_relative), cmd(description(is_relative), ' ', "0.1.0")
	{
		// --help lists them in this order (cli.cpp): input, main choices, tuning, output.
		for (TCLAP::Arg* a : std::initializer_list<TCLAP::Arg*>{&ref_arg, &est_arg, &ref_format_arg, &relation_arg,
																&align_arg, &scale_arg, &origin_arg})
			cmd.add(*a);
		if (relative)
		{
			cmd.add(delta_arg);
			cmd.add(all_pairs_arg);
		}
		for (TCLAP::Arg* a : std::initializer_list<TCLAP::Arg*>{&max_diff_arg, &offset_arg, &save_arg, &plot_arg})
			cmd.add(*a);
	}

	static std::string description(bool relative)
	{
		return relative
			? "Relative pose error (RPE) of an estimated trajectory against a reference, computed and printed as "
			  "evo_rpe does (same association, alignment, error definitions, statistics and layout)."
			: "Absolute pose error (APE) of an estimated trajectory against a reference, computed and printed as "
			  "evo_ape does (same association, alignment, error definitions, statistics and layout).";
	}

	apps::TrajectoryMetricOptions options()
	{
		if (!std::isfinite(max_diff_arg.getValue()) || max_diff_arg.getValue() < 0)
			throw UsageError("--t-max-diff must be a finite number >= 0");
		if (!std::isfinite(offset_arg.getValue())) throw UsageError("--t-offset must be finite");
		if (relative && delta_arg.getValue() < 1) throw UsageError("--delta must be >= 1");
		const std::string& save = save_arg.getValue();
		if (save.size() >= 4 && save.compare(save.size() - 4, 4, ".zip") == 0)
			throw UsageError("--save-results writes a directory of plain files (JSON, CSV, TUM), not evo's .zip: give a "
							 "directory ('" + save.substr(0, save.size() - 4) + "'), and zip it if needed");
		apps::TrajectoryMetricOptions c;
		c.relative = relative;
		c.ref_path = ref_arg.getValue();
		c.est_path = est_arg.getValue();
		c.ref_format = parse_enum<eval::TrajectoryFormat>(ref_format_arg.getValue(), "trajectory format");
		eval::AlignmentOptions alignment;
		alignment.align = align_arg.getValue();
		alignment.correct_scale = scale_arg.getValue();
		alignment.align_origin = origin_arg.getValue();
		eval::AssociationOptions association;
		association.t_max_diff = max_diff_arg.getValue();
		association.t_offset = offset_arg.getValue();
		const auto relation = eval::parse_pose_relation(relation_arg.getValue());
		c.ape.relation = c.rpe.relation = relation;
		c.ape.alignment = c.rpe.alignment = alignment;
		c.ape.association = c.rpe.association = association;
		c.rpe.delta = static_cast<std::size_t>(delta_arg.getValue());
		c.rpe.all_pairs = all_pairs_arg.getValue();
		c.save_results_dir = save_arg.getValue();
		c.plot_dir = plot_arg.getValue();
		return c;
	}
};
}  // namespace

namespace
{
/** evo's form `evo_ape tum REF EST`: a leading format word. "tum" is dropped (TUM is what swba reads);
 * evo's other formats are refused with what to do. Returns the arguments to parse. */
std::vector<char*> without_evo_format_word(int argc, char** argv)
{
	std::vector<char*> args(argv, argv + argc);
	if (argc < 2) return args;
	const std::string first = argv[1];
	if (first == "tum" && argc >= 4) args.erase(args.begin() + 1);
	if (first == "kitti" || first == "euroc" || first == "bag" || first == "bag2")
		throw UsageError("evo's '" + first + "' format is not read: convert the trajectories to TUM first (evo_traj " +
						 first + " ... --save_as_tum), then give them as REF EST");
	return args;
}
}  // namespace

/** Shared by `swba ape` and `swba rpe` (cmd_rpe.cpp registers the latter). */
int run_trajectory_metric_command(bool relative, int argc, char** argv)
{
	MetricCommandLine cl(relative);
	std::vector<char*> args = without_evo_format_word(argc, argv);
	if (auto rc = parse_command_line(cl.cmd, static_cast<int>(args.size()), args.data())) return *rc;
	apps::run_trajectory_metric(cl.options(), std::cout, std::cerr);
	return 0;
}

namespace
{
int run_ape(int argc, char** argv) { return run_trajectory_metric_command(false, argc, argv); }
SWBA_REGISTER_COMMAND("ape", "absolute pose error of a trajectory vs a reference (as evo_ape)", run_ape);
}  // namespace
}  // namespace swba::app
