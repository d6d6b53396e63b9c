#include "reading_gate.h"

#include <swba/factors/planar.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include <algorithm>
#include <limits>

namespace swba::estimators::detail
{
std::shared_ptr<Factor> model_reading_factor(PoseModel model, std::shared_ptr<Factor> f, const Eigen::VectorXd& sigma)
{
	if (model == PoseModel::Planar)
		f = std::make_shared<SubspaceFactor>(std::move(f), std::vector<int>{0, 1},
											 std::vector<std::vector<int>>{planar_pose_coordinates(), {0, 1}});
	f->set_information(sigma.cwiseInverse().cwiseAbs2().asDiagonal().toDenseMatrix());
	return f;
}

bool ReadingGate::residual(const Eigen::Vector3d& p, const Observation& o, const mrpt::poses::CPose3D& sensor,
						   const double* pose_x, Eigen::VectorXd& r, RowMajorMatrix* JT) const
{
	const auto f = model_reading_factor(model_, std::make_shared<RangeBearingXyzFactor>(o.z, sensor), reading_sigma(o));
	const double* x[2] = {pose_x, p.data()};
	r.resize(f->residual_dim());
	if (JT) JT->resize(f->residual_dim(), f->tangent_dims()[0]);
	double* jac[2] = {JT ? JT->data() : nullptr, nullptr};
	return f->evaluate(x, r.data(), jac) && r.allFinite();
}

double ReadingGate::distance(const Eigen::Vector3d& p, std::size_t n, const Observation& o,
							 const mrpt::poses::CPose3D& sensor, const double* pose_x,
							 const Eigen::MatrixXd* pose_cov) const
{
	Eigen::VectorXd r;
	RowMajorMatrix JT;
	if (!residual(p, o, sensor, pose_x, r, pose_cov ? &JT : nullptr)) return std::numeric_limits<double>::infinity();
	Eigen::MatrixXd S = reading_sigma(o).cwiseAbs2().asDiagonal();
	S *= 1.0 + 1.0 / static_cast<double>(std::max<std::size_t>(n, 1));
	if (pose_cov) S += JT * (*pose_cov) * JT.transpose();
	return r.dot(S.ldlt().solve(r));
}

void ReadingGate::centre_on(const Manifold& M, const double* x0, const mrpt::poses::CPose3D& sensor,
							const std::vector<GatedReading>& readings)
{
	const int d = M.tangent_size();
	centre_.assign(x0, x0 + M.ambient_size());
	const Eigen::MatrixXd P_inv = newest_pose_cov_.inverse();
	std::vector<double> next(centre_.size());
	Eigen::VectorXd delta(d), r;
	RowMajorMatrix JT;
	constexpr int kMaxIterations = 10;
	for (int it = 0; it < kMaxIterations; it++)
	{
		M.minus(centre_.data(), x0, delta.data());
		Eigen::MatrixXd A = P_inv;
		Eigen::VectorXd g = P_inv * delta;
		for (const GatedReading& gr : readings)
		{
			if (!residual(gr.point, *gr.o, sensor, centre_.data(), r, &JT)) continue;
			const double n = static_cast<double>(std::max<std::size_t>(gr.n, 1));
			const Eigen::VectorXd s_inv = reading_sigma(*gr.o).cwiseAbs2().cwiseInverse() / (1.0 + 1.0 / n);
			const double w = 1.0 / (1.0 + r.dot(s_inv.cwiseProduct(r)) / threshold_);  // Cauchy
			A.noalias() += w * JT.transpose() * s_inv.asDiagonal() * JT;
			g.noalias() += w * JT.transpose() * s_inv.cwiseProduct(r);
		}
		const Eigen::VectorXd step = -A.ldlt().solve(g);
		if (!step.allFinite()) break;
		M.plus(centre_.data(), step.data(), next.data());
		centre_.swap(next);
		if (step.norm() < 1e-10) break;
	}
}
}  // namespace swba::estimators::detail
