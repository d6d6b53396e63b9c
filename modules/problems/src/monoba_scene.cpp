// The synthetic scene of monocular bundle adjustment (see monoba.h and doc/monoba.md).
#include <swba/core/manifold.h>
#include <swba/core/validation.h>
#include <swba/problems/monoba.h>

#include <cmath>
#include <random>
#include <stdexcept>

namespace swba::problems
{
namespace
{
Eigen::Vector3d translation(const mrpt::poses::CPose3D& p) { return Eigen::Vector3d(p.x(), p.y(), p.z()); }

/** The scene's random streams: points, observations and initial depths from one, pose noise from a
 * second one, so that enabling pose noise does not change the points. One normal distribution serves
 * both, as it always has (it may carry a drawn value from one stream to the other). */
struct SceneRandom
{
	std::mt19937 points, poses;
	std::normal_distribution<double> gauss{0.0, 1.0};
	std::uniform_real_distribution<double> uxy{-4.0, 4.0}, uz{4.0, 8.0};

	explicit SceneRandom(unsigned seed)
	{
		std::seed_seq seq_points{seed, 1u}, seq_poses{seed, 2u};
		points.seed(seq_points);
		poses.seed(seq_poses);
	}
};

/** A quarter circle (θ_n = n·2π/(4N)), all cameras looking along world +z. */
std::vector<mrpt::poses::CPose3D> arc_poses(const MonoBASceneOptions& o)
{
	std::vector<mrpt::poses::CPose3D> poses;
	for (int n = 0; n < o.cameras; n++)
	{
		const double theta = n * (M_PI / 2.0) / o.cameras;
		const double r = o.arc_radius_m;
		poses.emplace_back(r * std::cos(theta) - r, r * std::sin(theta), std::sin(2.0 * theta), theta, 0.0, 0.0);
	}
	return poses;
}

/** Draws points until one is seen by two cameras (z > 0.1 m): its noisy observations (the first is
 * the host bearing) and its true and perturbed initial inverse depth in the host. */
MonoBAPoint draw_point(const MonoBASceneOptions& o, const std::vector<mrpt::poses::CPose3D>& true_poses,
					   SceneRandom& random)
{
	for (int attempt = 0;; attempt++)
	{
		if (attempt == 1000) throw std::runtime_error("monoba scene: cannot place a point seen by two cameras");
		MonoBAPoint pt;
		pt.world.x() = random.uxy(random.points);
		pt.world.y() = random.uxy(random.points);
		pt.world.z() = random.uz(random.points);
		std::vector<int> seen;
		std::vector<Eigen::Vector3d> in_cam;
		for (int n = 0; n < o.cameras; n++)
		{
			const Eigen::Matrix3d Rwc = true_poses[n].getRotationMatrix().asEigen();
			const Eigen::Vector3d pc = Rwc.transpose() * (pt.world - translation(true_poses[n]));
			if (pc.z() > 0.1)
			{
				seen.push_back(n);
				in_cam.push_back(pc);
			}
		}
		if (seen.size() < 2) continue;
		for (size_t k = 0; k < seen.size(); k++)
		{
			Eigen::Vector2d uv(in_cam[k].x() / in_cam[k].z(), in_cam[k].y() / in_cam[k].z());
			uv.x() += o.noise * random.gauss(random.points);
			uv.y() += o.noise * random.gauss(random.points);
			if (k == 0)
			{
				pt.host = seen[0];
				pt.host_bearing = uv;
			}
			else
				pt.observations.push_back({seen[k], uv});
		}
		const double z = in_cam[0].z();
		pt.true_inverse_depth = 1.0 / z;
		double z0 = z;
		if (o.depth_noise_m > 0)
			do
				z0 = z + o.depth_noise_m * random.gauss(random.points);
			while (z0 < 0.5);
		pt.initial_inverse_depth = 1.0 / z0;
		return pt;
	}
}

/** Cameras from pose_noise_from on start at T ⊞ δ, δ ~ N(0, diag(σ_t², σ_r²)). */
void perturb_initial_poses(const MonoBASceneOptions& o, MonoBAScene& scene, SceneRandom& random)
{
	const auto se3 = SE3Manifold::instance();
	for (int n = o.pose_noise_from; n < o.cameras; n++)
	{
		double x[12], delta[6];
		SE3Manifold::from_pose(scene.true_poses[n], x);
		for (int k = 0; k < 3; k++) delta[k] = o.pose_noise_m * random.gauss(random.poses);
		for (int k = 3; k < 6; k++) delta[k] = o.pose_noise_rad * random.gauss(random.poses);
		se3->plus(x, delta, x);
		scene.initial_poses[n] = SE3Manifold::to_pose(x);
	}
}
}  // namespace

void MonoBASceneOptions::validate() const
{
	const auto check = [](bool ok, const std::string& msg) {
		if (!ok) throw std::invalid_argument(msg);
	};
	check(cameras >= 2, "the number of cameras must be ≥ 2 (got " + std::to_string(cameras) + ")");
	check(points >= 1, "the number of points must be ≥ 1 (got " + std::to_string(points) + ")");
	check(arc_radius_m > 0 && std::isfinite(arc_radius_m), "the arc radius must be > 0");
	check(noise >= 0 && std::isfinite(noise), "the observation noise must be a number ≥ 0");
	check(depth_noise_m >= 0 && std::isfinite(depth_noise_m), "the depth noise must be a number ≥ 0");
	check(pose_noise_m >= 0 && std::isfinite(pose_noise_m) && pose_noise_rad >= 0 && std::isfinite(pose_noise_rad),
		  "the pose noise must be a number ≥ 0");
	check(pose_noise_from >= 0, "pose_noise_from must be ≥ 0");
}

MonoBAScene make_monoba_scene(const MonoBASceneOptions& o)
{
	validate_with_prefix(o, "monoba scene: ");
	MonoBAScene scene;
	scene.options = o;
	scene.true_poses = arc_poses(o);
	SceneRandom random(o.seed);
	for (int i = 0; i < o.points; i++) scene.points.push_back(draw_point(o, scene.true_poses, random));
	scene.initial_poses = scene.true_poses;
	if (o.pose_noise_m > 0 || o.pose_noise_rad > 0) perturb_initial_poses(o, scene, random);
	return scene;
}
}  // namespace swba::problems
