// The `swba monoba` application: one adjustment with its report, or the prior-weight sweep table.
#include <swba/apps/monoba.h>
#include <swba/core/file.h>

#include <fstream>
#include <ostream>
#include <stdexcept>

namespace swba::apps
{
MonoBASweepOptions MonoBAAppOptions::sweep_options() const
{
	MonoBASweepOptions sw;
	sw.seeds = sweep_seeds;
	sw.repetitions = repetitions;
	return sw;
}

void MonoBAAppOptions::validate() const
{
	scene.validate();
	adjustment.validate();
	sweep_options().validate();
}

std::string run_monoba_app(const MonoBAAppOptions& options, std::ostream& out, std::ostream& log)
{
	options.validate();
	std::string text;
	if (options.sweep)
	{
		const MonoBASweepOptions sw = options.sweep_options();
		text = format_sweep_table(run_prior_weight_sweep(options.scene, options.adjustment, sw), options.scene,
								  options.adjustment, sw);
	}
	else
	{
		const problems::MonoBAScene scene = problems::make_monoba_scene(options.scene);
		const MonoBAResult result = run_monoba(scene, options.adjustment, options.repetitions);
		text = format_monoba_report(scene, options.adjustment, result);
		if (!result.summary.is_solution_usable())
		{
			out << text;
			throw std::runtime_error("optimisation failed: " + result.summary.message);
		}
	}
	out << text;
	if (!options.out_path.empty())
	{
		write_text_file_atomically(options.out_path, text);
		out.flush();
		log << "Wrote " << options.out_path << "\n";
	}
	return text;
}
}  // namespace swba::apps
