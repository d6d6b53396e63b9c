// swba directba: direct (photometric) bundle adjustment with 4x4 patches (the course's 7-image set),
// or the same adjustment on a rendered synthetic room with ground truth (--synthetic).
#include <swba/estimators/directba.h>
#include <swba/io/ply.h>

#include <cmath>
#include <filesystem>
#include <iostream>

#include "cli.h"
#include "command.h"

namespace
{
std::vector<Eigen::Vector3d> centres(const std::vector<mrpt::poses::CPose3D>& poses)
{
	std::vector<Eigen::Vector3d> c;
	for (const auto& p : poses) c.emplace_back(p.x(), p.y(), p.z());
	return c;
}

std::vector<Eigen::Vector3d> positions(const std::vector<swba::io::DirectBAPoint>& pts)
{
	std::vector<Eigen::Vector3d> c;
	for (const auto& p : pts) c.push_back(p.position);
	return c;
}

int run_directba(int argc, char** argv)
{
	TCLAP::CmdLine cmd(
		"Direct (photometric) bundle adjustment: each point's 4x4 host patch against every image, sampled "
		"bilinearly at its projection; Huber kernel, points eliminated by Schur, first camera(s) fixed. "
		"DIR holds poses.txt, points.txt and 0.png..N-1.png (see doc/directba.md).",
		' ', "0.1.0");
	TCLAP::UnlabeledValueArg<std::string> dir("dir", "data set directory (not with --synthetic)", false, "", "DIR",
											  cmd);
	TCLAP::ValueArg<int> iterations("", "iterations", "maximum LM iterations (default 50)", false, 50, "K", cmd);
	TCLAP::ValueArg<double> sigma("", "sigma", "photometric noise sigma in gray levels (default 10)", false, 10.0,
								  "S", cmd);
	TCLAP::ValueArg<double> huber_delta(
		"", "huber-delta",
		"Huber threshold on the whitened patch residual norm |r|/sigma; 0 disables it (default "
		"sqrt(chi2_16(0.95)) = sqrt(26.296) = 5.128)",
		false, std::sqrt(swba::kChi2Patch95), "D", cmd);
	TCLAP::ValueArg<int> fixed_cameras("", "fixed-cameras",
									   "hold the first N cameras constant (gauge; default 1, --synthetic: 2)", false,
									   -1, "N", cmd);
	TCLAP::ValueArg<int> border("", "border", "margin in pixels between a patch and the image edge (default 1)",
								false, 1, "B", cmd);
	TCLAP::ValueArg<int> threads("", "threads", "threads for evaluation and assembly (default 1)", false, 1, "N",
								 cmd);
	TCLAP::ValueArg<std::string> ply_initial("", "ply-initial", "write the initial cameras and points as PLY", false,
											 "", "F.ply", cmd);
	TCLAP::ValueArg<std::string> ply_final("", "ply-final", "write the optimised cameras and points as PLY", false, "",
										   "F.ply", cmd);
	TCLAP::ValueArg<std::string> out_dir(
		"", "out", "write poses_initial.tum, poses_final.tum (world-from-camera) and points_final.ply here",
		false, "", "OUTDIR", cmd);
	TCLAP::SwitchArg synthetic("", "synthetic",
							   "run the synthetic check: render a textured room, perturb, recover, compare with "
							   "ground truth (exit 1 unless poses <= 1 mm / 0.05 deg and points <= 1 cm)",
							   cmd);
	TCLAP::SwitchArg quiet("q", "quiet", "do not print the per-iteration table", cmd);
	if (auto rc = swba::app::parse_command_line(cmd, argc, argv)) return *rc;

	swba::estimators::DirectBAOptions opt;
	opt.solver.max_iterations = iterations.getValue();
	opt.solver.num_threads = threads.getValue();
	opt.solver.progress_to_stdout = !quiet.getValue();
	opt.sigma = sigma.getValue();
	opt.huber_delta = huber_delta.getValue();
	opt.factor.border = border.getValue();
	if (huber_delta.getValue() < 0) throw swba::app::UsageError("--huber-delta must be >= 0");
	if (fixed_cameras.isSet() && fixed_cameras.getValue() < 0)
		throw swba::app::UsageError("--fixed-cameras must be >= 0");
	if (std::string why; !opt.is_valid(&why)) throw swba::app::UsageError(why);

	if (synthetic.getValue())
	{
		if (!dir.getValue().empty()) throw swba::app::UsageError("--synthetic takes no DIR");
		swba::io::SyntheticDirectBAOptions scene;
		if (fixed_cameras.isSet()) scene.fixed_cameras = fixed_cameras.getValue();
		const auto syn = swba::estimators::run_synthetic_direct_ba(scene, opt);
		std::cout << "Synthetic room (6 x 4 x 6 m textured box, see doc/directba.md): " << syn.num_cameras
				  << " cameras (" << scene.fixed_cameras << " fixed), " << syn.num_points << " points\n";
		std::cout << syn.result.summary.full_report() << swba::estimators::format_direct_ba_report(syn.result)
				  << swba::estimators::format_ground_truth_errors(syn.initial_errors, syn.final_errors);
		const auto& e = syn.final_errors;
		const bool pass = e.pose_translation_max_m <= 1e-3 && e.pose_rotation_max_deg <= 0.05 && e.point_max_m <= 0.01;
		std::cout << "Synthetic check: " << (pass ? "PASS" : "FAIL")
				  << " (poses <= 1 mm / 0.05 deg, every point <= 1 cm)\n";
		return pass ? 0 : 1;
	}

	if (dir.getValue().empty()) throw swba::app::UsageError("missing DIR (or use --synthetic)");
	opt.fixed_cameras = fixed_cameras.isSet() ? fixed_cameras.getValue() : 1;
	const auto data = swba::io::read_directba_dataset(dir.getValue());
	if (!out_dir.getValue().empty()) std::filesystem::create_directories(out_dir.getValue());
	std::cout << "Direct BA " << dir.getValue() << ": " << data.world_from_camera.size() << " cameras, "
			  << data.points.size() << " points, images " << data.images[0]->width << "x" << data.images[0]->height
			  << "; sigma " << opt.sigma << ", Huber " << opt.huber_delta << " (whitened), " << opt.fixed_cameras
			  << " camera(s) fixed\n";
	if (!ply_initial.getValue().empty())
	{
		swba::io::write_ply(ply_initial.getValue(), centres(data.world_from_camera), positions(data.points));
		std::cout << "Wrote " << ply_initial.getValue() << "\n";
	}
	const auto res = swba::estimators::run_direct_ba(data, opt);
	std::cout << res.summary.full_report() << swba::estimators::format_direct_ba_report(res);
	if (!res.summary.is_solution_usable()) throw std::runtime_error("optimisation failed: " + res.summary.message);
	if (!ply_final.getValue().empty())
	{
		swba::io::write_ply(ply_final.getValue(), centres(res.poses), res.points);
		std::cout << "Wrote " << ply_final.getValue() << "\n";
	}
	if (!out_dir.getValue().empty())
	{
		const std::filesystem::path out(out_dir.getValue());
		// The file's timestamps are all equal (1.46323e+09): TUM time = image index instead.
		std::vector<double> t;
		for (size_t i = 0; i < res.poses.size(); i++) t.push_back(double(i));
		swba::io::write_directba_tum((out / "poses_initial.tum").string(), t, data.world_from_camera);
		swba::io::write_directba_tum((out / "poses_final.tum").string(), t, res.poses);
		swba::io::write_ply((out / "points_final.ply").string(), centres(res.poses), res.points);
		std::cout << "Wrote " << (out / "poses_initial.tum").string() << ", poses_final.tum, points_final.ply\n";
	}
	return 0;
}
SWBA_REGISTER_COMMAND("directba", "direct (photometric) bundle adjustment, 4x4 patches", run_directba);
}  // namespace
