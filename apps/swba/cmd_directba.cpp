// swba directba: direct (photometric) bundle adjustment with 4x4 patches on a data set directory, or
// the same adjustment on a rendered synthetic room with ground truth (--synthetic). Logic in
// swba/apps/directba.h.
#include <swba/apps/directba.h>

#include <cmath>
#include <iostream>
#include <stdexcept>
#include <string>

#include "cli.h"
#include "command.h"

namespace
{
struct DirectbaCommandLine
{
	TCLAP::CmdLine cmd{
		"Direct (photometric) bundle adjustment: each point's 4x4 host patch against every image, sampled "
		"bilinearly at its projection; Huber kernel, points eliminated by Schur, first camera(s) fixed. "
		"DIR holds poses.txt, points.txt and 0.png..N-1.png (see doc/directba.md).",
		' ', "0.1.0"};
	TCLAP::UnlabeledValueArg<std::string> dir{"DIR", "data set directory (not with --synthetic)", false, "", "DIR", cmd};
	TCLAP::SwitchArg synthetic{"", "synthetic",
							   "run the synthetic check: render a textured room, perturb, recover, compare with "
							   "ground truth (exit 1 unless poses <= 1 mm / 0.05 deg and points <= 1 cm)",
							   cmd};
	TCLAP::ValueArg<double> sigma{
		"", "sigma", "photometric noise sigma in gray levels (Default: 10)", false, 10.0, "S", cmd};
	TCLAP::ValueArg<double> huber_delta{"", "huber-delta",
										"Huber threshold on the whitened patch residual norm |r|/sigma; 0 disables it "
										"(Default: sqrt(chi2_16(0.95)) = sqrt(26.296) = 5.128)",
										false, std::sqrt(swba::kChi2Patch95), "D", cmd};
	TCLAP::ValueArg<int> fixed_cameras{
		"", "fixed-cameras", "hold the first N cameras constant (gauge) (Default: 1; with --synthetic: 2)", false, -1, "N", cmd};
	TCLAP::ValueArg<int> border{
		"", "border", "margin in pixels between a patch and the image edge (Default: 1)", false, 1, "B", cmd};
	TCLAP::ValueArg<int> iterations = swba::app::max_iterations_arg(cmd, 50, "iterations");
	TCLAP::ValueArg<int> threads = swba::app::threads_arg(cmd);
	TCLAP::ValueArg<std::string> ply_initial{
		"", "ply-initial", "write the initial cameras and points as PLY (Default: not written)", false, "", "F.ply", cmd};
	TCLAP::ValueArg<std::string> ply_final{
		"", "ply-final", "write the optimised cameras and points as PLY (Default: not written)", false, "", "F.ply", cmd};
	TCLAP::ValueArg<std::string> out_dir{
		"", "out", "write poses_initial.tum, poses_final.tum (world-from-camera) and points_final.ply here (Default: not written)", false, "",
		"OUTDIR", cmd};
	TCLAP::SwitchArg quiet = swba::app::quiet_arg(cmd);
};

/** The typed options; bad values and a missing or superfluous DIR are usage errors. */
swba::apps::DirectBAAppOptions options_from(DirectbaCommandLine& a)
{
	using swba::app::UsageError;
	swba::apps::DirectBAAppOptions o;
	swba::apps::DirectBAOptions& opt = o.adjustment;
	opt.solver.max_iterations = a.iterations.getValue();
	opt.solver.num_threads = a.threads.getValue();
	opt.solver.progress_to_stdout = !a.quiet.getValue();
	opt.sigma = a.sigma.getValue();
	opt.huber_delta = a.huber_delta.getValue();
	opt.factor.border = a.border.getValue();
	if (opt.solver.max_iterations < 0) throw UsageError("--iterations must be >= 0");
	if (opt.solver.num_threads < 1) throw UsageError("--threads must be >= 1");
	if (!(opt.sigma > 0) || !std::isfinite(opt.sigma)) throw UsageError("--sigma must be a number > 0");
	if (!(a.huber_delta.getValue() >= 0) || !std::isfinite(a.huber_delta.getValue()))
		throw UsageError("--huber-delta must be a number >= 0");
	if (a.fixed_cameras.isSet() && a.fixed_cameras.getValue() < 0) throw UsageError("--fixed-cameras must be >= 0");
	if (opt.factor.border < 0) throw UsageError("--border must be >= 0");
	swba::app::validate_usage(opt);
	o.synthetic = a.synthetic.getValue();
	o.dataset_dir = a.dir.getValue();
	if (o.synthetic && !o.dataset_dir.empty()) throw UsageError("--synthetic takes no DIR");
	if (o.synthetic && (a.ply_initial.isSet() || a.ply_final.isSet() || a.out_dir.isSet()))
		throw UsageError("--synthetic writes no files: --ply-initial, --ply-final and --out go with a DIR");
	if (!o.synthetic && o.dataset_dir.empty()) throw UsageError("missing DIR (or use --synthetic)");
	if (a.fixed_cameras.isSet()) o.scene.fixed_cameras = opt.fixed_cameras = a.fixed_cameras.getValue();
	o.ply_initial = a.ply_initial.getValue();
	o.ply_final = a.ply_final.getValue();
	o.out_dir = a.out_dir.getValue();
	return o;
}

/** The app; more fixed cameras than the data set has is a bad --fixed-cameras (exit 2), a failed synthetic
 * check an error line after its report (exit 1). */
int run_directba(DirectbaCommandLine& args)
{
	const auto options = options_from(args);
	swba::apps::DirectBAAppResult result;
	try
	{
		result = swba::apps::run_directba_app(options, std::cout, std::cerr);
	}
	catch (const swba::apps::DirectBAFixedCamerasError& e)
	{
		throw swba::app::UsageError("--fixed-cameras " + std::to_string(e.fixed_cameras) + " is more than the " +
									std::to_string(e.num_cameras) + " cameras of " +
									(options.synthetic ? "the synthetic room" : "'" + options.dataset_dir + "'"));
	}
	if (options.synthetic && !result.synthetic_pass)
		throw std::runtime_error(result.result.summary.is_solution_usable()
									 ? "synthetic check failed: the recovery misses its bounds (poses <= 1 mm / "
									   "0.05 deg, every point <= 1 cm)"
									 : "synthetic check failed: optimisation failed: " + result.result.summary.message);
	return 0;
}
SWBA_REGISTER_COMMAND("directba", "direct (photometric) bundle adjustment, 4x4 patches",
					  swba::app::parsed_command<DirectbaCommandLine>(run_directba));
}  // namespace
