// The `swba directba` application: the adjustment of a data set with its outputs, or the synthetic
// check against ground truth (see directba.h).
#include <swba/apps/directba.h>
#include <swba/eval/trajectory.h>
#include <swba/io/ply.h>

#include <filesystem>
#include <ostream>
#include <stdexcept>

namespace swba::apps
{
namespace
{
std::vector<Eigen::Vector3d> centres(const std::vector<mrpt::poses::CPose3D>& poses)
{
	std::vector<Eigen::Vector3d> c;
	for (const auto& p : poses) c.emplace_back(p.x(), p.y(), p.z());
	return c;
}

std::vector<Eigen::Vector3d> positions(const std::vector<io::DirectBAPoint>& pts)
{
	std::vector<Eigen::Vector3d> c;
	for (const auto& p : pts) c.push_back(p.position);
	return c;
}

DirectBAAppResult run_synthetic_check(const DirectBAAppOptions& options, std::ostream& out)
{
	const auto syn = run_synthetic_direct_ba(options.scene, options.adjustment);
	out << "Synthetic room (6 x 4 x 6 m textured box, see doc/directba.md): " << syn.num_cameras << " cameras ("
		<< options.scene.fixed_cameras << " fixed), " << syn.num_points << " points\n";
	out << syn.result.summary.full_report() << format_direct_ba_report(syn.result)
		<< format_direct_ba_ground_truth_errors(syn.initial_errors, syn.final_errors);
	const auto& e = syn.final_errors;
	DirectBAAppResult r;
	r.result = syn.result;
	r.synthetic_pass = e.pose_translation_max_m <= 1e-3 && e.pose_rotation_max_deg <= 0.05 && e.point_max_m <= 0.01;
	out << "Synthetic check: " << (r.synthetic_pass ? "PASS" : "FAIL")
		<< " (poses <= 1 mm / 0.05 deg, every point <= 1 cm)\n";
	return r;
}

/** poses_initial.tum, poses_final.tum (world-from-camera) and points_final.ply in options.out_dir. */
void write_outputs(const DirectBAAppOptions& options, const io::DirectBADataset& data, const DirectBAResult& res,
				   std::ostream& log)
{
	const std::filesystem::path dir(options.out_dir);
	// The file's timestamps are all equal (1.46323e+09): TUM time = image index instead.
	eval::Trajectory initial, refined;
	for (size_t i = 0; i < res.poses.size(); i++)
	{
		initial.push_back(double(i), data.world_from_camera[i]);
		refined.push_back(double(i), res.poses[i]);
	}
	eval::write_tum((dir / "poses_initial.tum").string(), initial);
	eval::write_tum((dir / "poses_final.tum").string(), refined);
	io::write_ply((dir / "points_final.ply").string(), centres(res.poses), res.points);
	log << "Wrote " << (dir / "poses_initial.tum").string() << ", poses_final.tum, points_final.ply\n";
}

DirectBAAppResult run_on_dataset(const DirectBAAppOptions& options, std::ostream& out, std::ostream& log)
{
	const DirectBAOptions& opt = options.adjustment;
	const auto data = io::read_directba_dataset(options.dataset_dir);
	if (!options.out_dir.empty()) std::filesystem::create_directories(options.out_dir);
	out << "Direct BA " << options.dataset_dir << ": " << data.world_from_camera.size() << " cameras, "
		<< data.points.size() << " points, images " << data.images[0]->width << "x" << data.images[0]->height
		<< "; sigma " << opt.sigma << ", Huber " << opt.huber_delta << " (whitened), " << opt.fixed_cameras
		<< " camera(s) fixed\n";
	if (!options.ply_initial.empty())
	{
		io::write_ply(options.ply_initial, centres(data.world_from_camera), positions(data.points));
		out.flush();
		log << "Wrote " << options.ply_initial << "\n";
	}
	DirectBAAppResult r;
	r.result = run_direct_ba(data, opt);
	out << r.result.summary.full_report() << format_direct_ba_report(r.result);
	out.flush();
	if (!r.result.summary.is_solution_usable())
		throw std::runtime_error("optimisation failed: " + r.result.summary.message);
	if (!options.ply_final.empty())
	{
		io::write_ply(options.ply_final, centres(r.result.poses), r.result.points);
		log << "Wrote " << options.ply_final << "\n";
	}
	if (!options.out_dir.empty()) write_outputs(options, data, r.result, log);
	return r;
}
}  // namespace

void DirectBAAppOptions::validate() const
{
	adjustment.validate();
	if (synthetic && !dataset_dir.empty()) throw std::invalid_argument("the synthetic check takes no data set directory");
	if (!synthetic && dataset_dir.empty()) throw std::invalid_argument("no data set directory");
}

DirectBAAppResult run_directba_app(const DirectBAAppOptions& options, std::ostream& out, std::ostream& log)
{
	options.validate();
	return options.synthetic ? run_synthetic_check(options, out) : run_on_dataset(options, out, log);
}
}  // namespace swba::apps
