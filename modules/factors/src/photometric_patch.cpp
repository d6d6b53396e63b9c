#include <swba/core/manifold.h>
#include <swba/factors/photometric_patch.h>

#include <cmath>
#include <stdexcept>

namespace swba
{
bool bilinear_in_bounds(const IntensityImage& image, double u, double v)
{
	if (!std::isfinite(u) || !std::isfinite(v)) return false;
	// floor(u) + 1 ≤ width − 1  ⇔  u < width − 1 (and likewise for v).
	return u >= 0.0 && v >= 0.0 && u < double(image.width - 1) && v < double(image.height - 1);
}

bool sample_bilinear(const IntensityImage& image, double u, double v, BilinearSample& out)
{
	if (!bilinear_in_bounds(image, u, v)) return false;
	const int x0 = static_cast<int>(std::floor(u));
	const int y0 = static_cast<int>(std::floor(v));
	const double a = u - x0, b = v - y0;
	const float* row0 = image.pixels.data() + size_t(y0) * size_t(image.width) + size_t(x0);
	const float* row1 = row0 + image.width;
	const double i00 = row0[0], i10 = row0[1], i01 = row1[0], i11 = row1[1];
	out.value = (1 - a) * (1 - b) * i00 + a * (1 - b) * i10 + (1 - a) * b * i01 + a * b * i11;
	out.du = (1 - b) * (i10 - i00) + b * (i11 - i01);
	out.dv = (1 - a) * (i01 - i00) + a * (i11 - i10);
	return true;
}

PhotometricPatchFactor::PhotometricPatchFactor(const PatchValues& host_patch,
											   std::shared_ptr<const IntensityImage> target,
											   const PatchCameraIntrinsics& intrinsics, const Options& options)
	: Factor(kPatchSize, {SE3Manifold::kTangent, 3}),
	  host_patch_(host_patch),
	  target_(std::move(target)),
	  K_(intrinsics),
	  opt_(options)
{
	if (!target_ || target_->empty())
		throw std::invalid_argument("PhotometricPatchFactor: empty target image");
	if (target_->pixels.size() != size_t(target_->width) * size_t(target_->height))
		throw std::invalid_argument("PhotometricPatchFactor: image buffer size does not match width × height");
	if (opt_.border < 0) throw std::invalid_argument("PhotometricPatchFactor: border must be ≥ 0");
	if (!(K_.fx > 0) || !(K_.fy > 0)) throw std::invalid_argument("PhotometricPatchFactor: focal lengths must be > 0");
}

bool PhotometricPatchFactor::project(const double* pose_wc, const double* point_w, double& u, double& v) const
{
	const auto T = se3_view(pose_wc);
	const Eigen::Vector3d pw(point_w[0], point_w[1], point_w[2]);
	const Eigen::Vector3d pc = T.leftCols<3>().transpose() * (pw - T.col(3));
	if (!(pc.z() > opt_.min_depth)) return false;
	u = K_.fx * pc.x() / pc.z() + K_.cx;
	v = K_.fy * pc.y() / pc.z() + K_.cy;
	return std::isfinite(u) && std::isfinite(v);
}

bool PhotometricPatchFactor::patch_inside(double u, double v) const
{
	if (!std::isfinite(u) || !std::isfinite(v)) return false;
	// Samples span [u−2, u+1]; bilinear reads ⌊x⌋ and ⌊x⌋+1. With border b:
	// ⌊u−2⌋ ≥ b ⇔ u ≥ 2 + b, and ⌊u+1⌋ + 1 ≤ W − 1 − b ⇔ u < W − 2 − b.
	const double b = opt_.border;
	return u >= 2.0 + b && v >= 2.0 + b && u < double(target_->width) - 2.0 - b &&
		   v < double(target_->height) - 2.0 - b;
}

bool PhotometricPatchFactor::evaluate(const double* const* x, double* residual, double* const* jacobians) const
{
	const auto T = se3_view(x[0]);
	const Eigen::Matrix3d Rt = T.leftCols<3>().transpose();
	const Eigen::Vector3d pw(x[1][0], x[1][1], x[1][2]);
	const Eigen::Vector3d pc = Rt * (pw - T.col(3));
	if (!(pc.z() > opt_.min_depth)) return false;
	const double iz = 1.0 / pc.z();
	const double u = K_.fx * pc.x() * iz + K_.cx;
	const double v = K_.fy * pc.y() * iz + K_.cy;
	if (!patch_inside(u, v)) return false;

	const bool want_pose = jacobians && jacobians[0];
	const bool want_point = jacobians && jacobians[1];
	// ∂(u,v)/∂p_c
	Eigen::Matrix<double, 2, 3> d_uv_d_pc;
	d_uv_d_pc << K_.fx * iz, 0.0, -K_.fx * pc.x() * iz * iz, 0.0, K_.fy * iz, -K_.fy * pc.y() * iz * iz;
	// ∂p_c/∂δ (pose, δ = [ρ, ω]) and ∂p_c/∂p_w.
	Eigen::Matrix<double, 3, 6> d_pc_d_pose;
	d_pc_d_pose.leftCols<3>() = -Eigen::Matrix3d::Identity();
	d_pc_d_pose.rightCols<3>() = skew(pc);
	const Eigen::Matrix<double, 2, 6> d_uv_d_pose = d_uv_d_pc * d_pc_d_pose;
	const Eigen::Matrix<double, 2, 3> d_uv_d_point = d_uv_d_pc * Rt;

	using RowMajor16x6 = Eigen::Matrix<double, kPatchSize, 6, Eigen::RowMajor>;
	using RowMajor16x3 = Eigen::Matrix<double, kPatchSize, 3, Eigen::RowMajor>;
	for (int k = 0; k < kPatchSize; k++)
	{
		BilinearSample s;
		// patch_inside() guarantees this succeeds; the check is a second guard against reading outside.
		if (!sample_bilinear(*target_, u + patch_offset_x(k), v + patch_offset_y(k), s)) return false;
		residual[k] = host_patch_[k] - s.value;
		const Eigen::RowVector2d d_r_d_uv(-s.du, -s.dv);
		if (want_pose) Eigen::Map<RowMajor16x6>(jacobians[0]).row(k) = d_r_d_uv * d_uv_d_pose;
		if (want_point) Eigen::Map<RowMajor16x3>(jacobians[1]).row(k) = d_r_d_uv * d_uv_d_point;
	}
	return true;
}
}  // namespace swba
