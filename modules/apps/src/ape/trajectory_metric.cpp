// swba ape / swba rpe: read both trajectories, compute the metric, print, save, plot.
#include <swba/apps/trajectory_metric.h>
#include <swba/eval/report.h>

#include <ostream>
#include <stdexcept>


namespace swba::apps
{
using namespace eval;

MetricResult run_trajectory_metric(const TrajectoryMetricOptions& c, std::ostream& out, std::ostream& log)
{
	const Trajectory ref = read_trajectory(c.ref_path, c.ref_format);
	const Trajectory est = read_trajectory(c.est_path, c.est_format);
	if (ref.empty()) throw std::runtime_error(c.ref_path + ": no poses in the reference trajectory");
	if (est.empty()) throw std::runtime_error(c.est_path + ": no poses in the estimated trajectory");
	const MetricResult r = c.relative ? compute_rpe(ref, est, c.rpe) : compute_ape(ref, est, c.ape);
	out << format_text_report(r) << "\n";
	out.flush();
	if (!c.save_results_dir.empty())
		for (const auto& f : save_results(r, c.save_results_dir)) log << "saved " << f << "\n";
	if (!c.plot_dir.empty())
	{
		const std::string prefix = c.relative ? "rpe" : "ape";
		const auto traj = plot_trajectories_top_view(c.plot_dir, prefix + "_trajectories", {"reference", r.ref},
													 {{"estimate " + alignment_title(r.alignment_options), r.est}},
													 "trajectories (top view)", c.plot);
		const auto errs = plot_error_over_time(c.plot_dir, prefix + "_errors", r, c.plot);
		for (const auto* p : {&traj, &errs})
		{
			if (!p->note.empty())
			{
				log << p->note << "\n";
				break;	// one line is enough: the reason is the same for both plots
			}
			for (const auto& f : p->files)
				if (f.size() > 4 && (f.compare(f.size() - 4, 4, ".png") == 0 || f.compare(f.size() - 4, 4, ".svg") == 0))
					log << "plot " << f << "\n";
		}
	}
	return r;
}
}  // namespace swba::apps
