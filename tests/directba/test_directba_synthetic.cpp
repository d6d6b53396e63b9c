// Synthetic direct BA with ground truth: the rendered room is consistent with the photometric model
// at the true values, the perturbation is several pixels, and the adjustment recovers the truth
// (poses within 1 mm / 0.05°, every point within 1 cm).
#include <swba/apps/directba.h>
#include <swba/problems/directba_synthetic.h>

#include <gtest/gtest.h>

using namespace swba;

namespace
{
std::vector<Eigen::Vector3d> positions(const io::DirectBADataset& d)
{
	std::vector<Eigen::Vector3d> p;
	for (const auto& q : d.points) p.push_back(q.position);
	return p;
}
}  // namespace

TEST(DirectBASynthetic, RendererIsDeterministicAndTextured)
{
	const auto a = problems::make_synthetic_directba();
	const auto b = problems::make_synthetic_directba();
	ASSERT_EQ(a.truth.images.size(), 6u);
	EXPECT_EQ(a.truth.images[3]->pixels, b.truth.images[3]->pixels);
	EXPECT_EQ(a.initial.points[10].position, b.initial.points[10].position);
	EXPECT_GT(a.truth.points.size(), 300u);
	// Host patch = host image at integer pixels around the true projection (u0, v0).
	const auto& img = *a.truth.images[a.host_camera[0]];
	double lo = 1e9, hi = -1e9;
	for (float v : img.pixels)
	{
		lo = std::min<double>(lo, v);
		hi = std::max<double>(hi, v);
	}
	EXPECT_GT(hi - lo, 100.0);
	EXPECT_GE(lo, 0.0);
	EXPECT_LE(hi, 255.0);
	// Fixed cameras are not perturbed, the others are.
	EXPECT_EQ(a.initial.world_from_camera[0], a.truth.world_from_camera[0]);
	EXPECT_EQ(a.initial.world_from_camera[1], a.truth.world_from_camera[1]);
	EXPECT_NE(a.initial.world_from_camera[2], a.truth.world_from_camera[2]);
}

TEST(DirectBASynthetic, GroundTruthFitsThePhotometricModel)
{
	// At the true values the residual is only interpolation/quantisation/patch-warp error; at the
	// perturbed values it is much larger. This is what makes the recovery test meaningful.
	const auto syn = problems::make_synthetic_directba();
	apps::DirectBAOptions opt;
	const auto at_truth = apps::direct_ba_stats(syn.truth, syn.truth.world_from_camera, positions(syn.truth), opt);
	const auto at_start =
		apps::direct_ba_stats(syn.initial, syn.initial.world_from_camera, positions(syn.initial), opt);
	EXPECT_LT(at_truth.pixel_rms, 0.5);
	EXPECT_GT(at_start.pixel_rms, 5 * at_truth.pixel_rms);
	EXPECT_GT(at_truth.evaluated, 1800);
	// The perturbation is several pixels.
	const auto e0 = apps::direct_ba_ground_truth_errors(syn.truth, syn.initial.world_from_camera, positions(syn.initial));
	EXPECT_GT(e0.reprojection_mean_px, 2.0);
	EXPECT_EQ(apps::direct_ba_ground_truth_errors(syn.truth, syn.truth.world_from_camera, positions(syn.truth))
				  .reprojection_max_px,
			  0.0);
}

TEST(DirectBASynthetic, RecoversGroundTruthFromSeveralPixelsOfPerturbation)
{
	problems::SyntheticDirectBAOptions scene;
	apps::DirectBAOptions opt;
	opt.solver.max_iterations = 50;
	const auto syn = apps::run_synthetic_direct_ba(scene, opt);
	const auto& r = syn.result;
	std::cout << r.summary.full_report() << apps::format_direct_ba_report(r)
			  << apps::format_direct_ba_ground_truth_errors(syn.initial_errors, syn.final_errors);
	ASSERT_TRUE(r.summary.is_solution_usable()) << r.summary.message;
	EXPECT_GT(syn.initial_errors.reprojection_mean_px, 2.0);
	EXPECT_LT(r.summary.final_cost, 0.1 * r.summary.initial_cost);
	EXPECT_LE(syn.final_errors.pose_translation_max_m, 1e-3);
	EXPECT_LE(syn.final_errors.pose_rotation_max_deg, 0.05);
	EXPECT_LE(syn.final_errors.point_max_m, 0.01);
	// Against the start, the errors must have shrunk by a large factor (not a trivially easy start).
	EXPECT_GT(syn.initial_errors.pose_translation_max_m, 10 * syn.final_errors.pose_translation_max_m);
	EXPECT_GT(syn.initial_errors.point_max_m, 5 * syn.final_errors.point_max_m);
}
