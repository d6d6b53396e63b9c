// swba_evaluate: a trajectory evaluated with swba::eval as evo evaluates it: APE and RPE of an
// estimate against a reference (TUM files), evo's text blocks, the statistics as JSON and CSV, the
// per-pose errors, evo's result files and the plots of evo_ape --plot.
//   swba_evaluate REF.tum EST.tum OUT_DIR
#include <swba/eval/evaluation.h>
#include <swba/eval/plot.h>
#include <swba/eval/report.h>

#include <exception>
#include <fstream>
#include <iostream>
#include <string>

namespace
{
/** Prints a plot's note (gnuplot missing or failed) when there is one. */
void say(const swba::eval::PlotOutput& o)
{
	if (!o.note.empty()) std::cerr << o.note << "\n";
}

void evaluate(const std::string& ref_path, const std::string& est_path, const std::string& out)
{
	using namespace swba::eval;
	const Trajectory gt = read_tum(ref_path);
	const Trajectory estimate = read_tum(est_path);

	MetricResult r = compute_ape(gt, estimate, ApeOptions{});      // or compute_rpe(gt, estimate, RpeOptions{})
	std::string text = format_text_report(r);                     // evo's block
	std::string json = statistics_json(r.stats);                  // one JSON object (round-trip numbers)
	std::cout << text << "\n" << json << "\n";
	MetricResult rpe = compute_rpe(gt, estimate, RpeOptions{});   // consecutive pairs, translation part
	std::cout << format_text_report(rpe);

	save_results(r, out + "/ape");                                // evo's files: stats, errors, result, aligned estimate
	write_statistics_json(out + "/ape_stats_only.json", r.stats);
	write_statistics_csv(std::cout, {{"APE", r.stats}, {"RPE", rpe.stats}});  // one row per name
	std::ofstream stream(out + "/ape_errors_only.csv");
	write_errors_csv(stream, r);                                  // per-pose errors

	say(plot_trajectories_top_view(out + "/plots", "trajectories", {"reference", gt}, {{"estimate", estimate}}));
	say(plot_error_over_time(out + "/plots", "ape", r));          // error, rmse/median/mean lines, mean ± std band
	say(plot_trajectory_colormap(out + "/plots", "colormap",      // path coloured by a per-pose error
								 {"APE along the path", {"reference", r.ref}, {"estimate", r.est}, r.errors, "APE (m)"}));
	say(plot_rmse_vs_window(out + "/plots", "rmse_vs_window",
							{{"sliding window", {5, 10, 20}, {0.021, 0.017, 0.0155}}},   // {label, window sizes, rmse}
							{{"EKF", 0.0160638}, {"batch", 0.0121}}));                     // horizontal reference lines
}
}  // namespace

int main(int argc, char** argv)
{
	if (argc != 4)
	{
		std::cerr << "usage: swba_evaluate REF.tum EST.tum OUT_DIR\n";
		return 2;
	}
	try
	{
		evaluate(argv[1], argv[2], argv[3]);
		return 0;
	}
	catch (const std::exception& e)
	{
		std::cerr << "swba_evaluate: error: " << e.what() << "\n";
		return 1;
	}
}
