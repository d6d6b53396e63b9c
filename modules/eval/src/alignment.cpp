// Trajectory alignment (Umeyama SE(3)/Sim(3)/scale, origin) with evo's semantics.
#include "swba/eval/alignment.h"

#include <Eigen/Geometry>
#include <cmath>
#include <Eigen/SVD>
#include <limits>
#include <stdexcept>

namespace swba::eval
{
Eigen::Matrix4d Sim3::matrix() const
{
	Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
	T.topLeftCorner<3, 3>() = scale * R;
	T.topRightCorner<3, 1>() = t;
	return T;
}

Eigen::Matrix4d to_matrix(const mrpt::poses::CPose3D& pose)
{
	Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
	T.topLeftCorner<3, 3>() = pose.getRotationMatrix().asEigen();
	T.topRightCorner<3, 1>() << pose.x(), pose.y(), pose.z();
	return T;
}

mrpt::poses::CPose3D from_matrix(const Eigen::Matrix4d& T)
{
	const Eigen::Matrix3d R = T.topLeftCorner<3, 3>();
	const Eigen::Vector3d t = T.topRightCorner<3, 1>();
	return mrpt::poses::CPose3D::FromRotationAndTranslation(R, t);
}

Sim3 umeyama_alignment(const Eigen::Matrix3Xd& src, const Eigen::Matrix3Xd& dst, bool with_scale)
{
	if (src.cols() != dst.cols())
		throw std::invalid_argument("umeyama_alignment: " + std::to_string(src.cols()) + " source points but " +
									std::to_string(dst.cols()) + " destination points");
	if (src.cols() == 0) throw std::invalid_argument("umeyama_alignment: no points to align");
	// evo's test: the cross-covariance of the centred point sets needs rank >= 2 (two singular values
	// above machine epsilon), else the rotation is not determined (1 or 2 poses, collinear positions).
	const Eigen::Matrix3Xd src_c = src.colwise() - src.rowwise().mean();
	const Eigen::Matrix3Xd dst_c = dst.colwise() - dst.rowwise().mean();
	const Eigen::Matrix3d cov = dst_c * src_c.transpose() / static_cast<double>(src.cols());
	const Eigen::Vector3d sv = Eigen::JacobiSVD<Eigen::Matrix3d>(cov).singularValues();
	if ((sv.array() > std::numeric_limits<double>::epsilon()).count() < 2)
		throw std::invalid_argument("Degenerate covariance rank, Umeyama alignment is not possible (" +
									std::to_string(src.cols()) +
									" poses: their positions must span a plane, 3 or more not on one line)");
	// Eigen::umeyama returns [c·R t; 0 1] with det R = +1 (it applies S = diag(1,1,−1) when
	// det U · det V < 0, exactly as Umeyama's paper and evo).
	const Eigen::Matrix4d T = Eigen::umeyama(src, dst, with_scale);
	Sim3 s;
	const Eigen::Matrix3d cR = T.topLeftCorner<3, 3>();
	s.scale = with_scale ? cR.colwise().norm().mean() : 1.0;
	s.R = cR / s.scale;
	s.t = T.topRightCorner<3, 1>();
	return s;
}

Sim3 yaw_alignment(const Eigen::Matrix3Xd& src, const Eigen::Matrix3Xd& dst)
{
	if (src.cols() != dst.cols() || src.cols() == 0)
		throw std::invalid_argument("yaw_alignment: " + std::to_string(src.cols()) + " source points and " +
									std::to_string(dst.cols()) + " destination points");
	const Eigen::Vector3d ms = src.rowwise().mean(), md = dst.rowwise().mean();
	const Eigen::Matrix3Xd s = src.colwise() - ms, d = dst.colwise() - md;
	const double c = (s.row(0).cwiseProduct(d.row(0)) + s.row(1).cwiseProduct(d.row(1))).sum();
	const double n = (s.row(0).cwiseProduct(d.row(1)) - s.row(1).cwiseProduct(d.row(0))).sum();
	if (std::hypot(c, n) <= std::numeric_limits<double>::epsilon())
		throw std::invalid_argument("yaw_alignment: the points' horizontal parts do not determine a yaw");
	Sim3 out;
	out.R = Eigen::AngleAxisd(std::atan2(n, c), Eigen::Vector3d::UnitZ()).toRotationMatrix();
	out.t = md - out.R * ms;
	return out;
}

AlignmentResult align_trajectory(Trajectory& est, const Trajectory& ref, const AlignmentOptions& options)
{
	if (est.size() != ref.size())
		throw std::invalid_argument("align_trajectory: trajectories are not associated (" + std::to_string(est.size()) +
									" vs " + std::to_string(ref.size()) + " poses)");
	AlignmentResult result;
	if (options.align || options.correct_scale)
	{
		const Sim3 umeyama = umeyama_alignment(est.positions(), ref.positions(), options.correct_scale);
		const bool only_scale = options.correct_scale && !options.align;
		result.transform.scale = umeyama.scale;
		if (!only_scale)
		{
			result.transform.R = umeyama.R;
			result.transform.t = umeyama.t;
		}
		const Sim3& a = result.transform;
		for (auto& p : est.poses)
		{
			const Eigen::Matrix3d Rp = p.getRotationMatrix().asEigen();
			const Eigen::Vector3d tp(p.x(), p.y(), p.z());
			// evo: scale the translation first, then left-multiply by [R t].
			const Eigen::Vector3d t_scaled = a.scale * tp;
			if (only_scale)
				p = mrpt::poses::CPose3D::FromRotationAndTranslation(Rp, t_scaled);
			else
			{
				const Eigen::Matrix3d R = a.R * Rp;
				const Eigen::Vector3d t = a.R * t_scaled + a.t;
				p = mrpt::poses::CPose3D::FromRotationAndTranslation(R, t);
			}
		}
	}
	if (options.align_origin)
	{
		if (est.empty()) throw std::invalid_argument("align_trajectory: cannot align the origin of an empty trajectory");
		const Eigen::Matrix4d est0 = to_matrix(est.poses.front());
		Eigen::Matrix4d est0_inv = Eigen::Matrix4d::Identity();
		est0_inv.topLeftCorner<3, 3>() = est0.topLeftCorner<3, 3>().transpose();
		est0_inv.topRightCorner<3, 1>() = -est0.topLeftCorner<3, 3>().transpose() * est0.topRightCorner<3, 1>();
		result.origin = to_matrix(ref.poses.front()) * est0_inv;
		for (auto& p : est.poses) p = from_matrix(result.origin * to_matrix(p));
	}
	return result;
}

std::string alignment_title(const AlignmentOptions& o)
{
	std::string title;
	if (o.align && !o.correct_scale)
		title = "(with SE(3) Umeyama alignment)";
	else if (o.align && o.correct_scale)
		title = "(with Sim(3) Umeyama alignment)";
	else if (o.correct_scale)
		title = "(scale corrected)";
	else if (!o.align_origin)
		title = "(not aligned)";
	if (o.align_origin) title += std::string(title.empty() ? "" : "\n") + "(with origin alignment)";
	return title;
}
}  // namespace swba::eval
