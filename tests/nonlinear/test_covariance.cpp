// Covariance recovery (swba/nonlinear/covariance.h) against the dense inverse of the same normal
// equations, for every linear solver, in a solve and afterwards, and in the minimum-norm gauge.
#include <gtest/gtest.h>

#include "random_draws.h"
#include <swba/core/lie.h>
#include <swba/nonlinear/covariance.h>
#include "support/dense_linearization.h"

#include <Eigen/Dense>
#include <algorithm>
#include <random>

using namespace swba;

namespace
{
/** r = T⁻¹·p − z: a point p (world) seen in the frame of pose T. */
class SeenPoint final : public Factor
{
   public:
	explicit SeenPoint(const Eigen::Vector3d& z) : Factor(3, {6, 3}), z_(z) {}
	bool evaluate(const double* const* x, double* residual, double* const* jac) const override
	{
		const auto T = se3_view(x[0]);
		const Eigen::Matrix3d R = T.leftCols<3>();
		const Eigen::Vector3d l = R.transpose() * (Eigen::Map<const Eigen::Vector3d>(x[1]) - T.col(3));
		Eigen::Map<Eigen::Vector3d>{residual} = l - z_;
		if (jac && jac[0])
		{
			Eigen::Map<Eigen::Matrix<double, 3, 6, Eigen::RowMajor>> J(jac[0]);
			J.leftCols<3>() = -Eigen::Matrix3d::Identity();
			J.rightCols<3>() = skew(l);
		}
		if (jac && jac[1]) Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>{jac[1]} = R.transpose();
		return true;
	}

   private:
	Eigen::Vector3d z_;
};

struct CovarianceScene
{
	Problem problem;
	std::vector<VariableId> poses, points;
};

/** 4 poses, 12 points, each point seen by three consecutive poses (so that the reduced system is not
 * full); pose 0 constant unless `free`. */
CovarianceScene make_covariance_scene(bool free, unsigned seed = 7)
{
	std::mt19937 rng(seed);
	std::normal_distribution<double> N(0, 1);
	CovarianceScene s;
	for (int i = 0; i < 4; i++)
		s.poses.push_back(s.problem.add_pose(mrpt::poses::CPose3D(0.5 * i, 0.1 * i, 0.05 * i, 0.3 * i, -0.05 * i, 0.02 * i)));
	for (int j = 0; j < 12; j++)
		s.points.push_back(s.problem.add_variable((Eigen::Vector3d(3, 0, 0) + normal3(N, rng)), euclidean_manifold(3),
												  Group::Eliminable));
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 12; j++)
		{
			if ((j + i) % 4 == 0) continue;
			auto f = std::make_shared<SeenPoint>((Eigen::Vector3d(3, 0, 0) + normal3(N, rng)));
			f->set_sigma(0.1 + 0.01 * j);
			s.problem.add_factor(f, {s.poses[i], s.points[j]});
		}
	if (!free) s.problem.set_constant(s.poses[0]);
	return s;
}

/** `num_poses` poses along a line, three points per pose, each seen by it and the next two: the
 * reduced system is banded, so poses far apart share no entry of its factor. Pose 0 constant. */
CovarianceScene make_chain_scene(int num_poses, unsigned seed = 9)
{
	std::mt19937 rng(seed);
	std::normal_distribution<double> N(0, 1);
	CovarianceScene s;
	for (int i = 0; i < num_poses; i++)
		s.poses.push_back(s.problem.add_pose(mrpt::poses::CPose3D(0.5 * i, 0.1 * i, 0, 0.05 * i, 0, 0)));
	for (int i = 0; i < num_poses; i++)
		for (int k = 0; k < 3; k++)
		{
			const VariableId p = s.problem.add_variable(Eigen::Vector3d(0.5 * i + 3, k - 1.0, 0) + 0.3 * normal3(N, rng),
														 euclidean_manifold(3), Group::Eliminable);
			s.points.push_back(p);
			for (int j = i; j < std::min(i + 3, num_poses); j++)
			{
				auto f = std::make_shared<SeenPoint>(Eigen::Vector3d(3, k - 1.0, 0) + 0.1 * normal3(N, rng));
				f->set_sigma(0.1);
				s.problem.add_factor(f, {s.poses[j], p});
			}
		}
	s.problem.set_constant(s.poses[0]);
	return s;
}

/** The non-constant variables and the dense inverse of their normal equations at the current values. */
struct Dense
{
	std::vector<VariableId> order;
	DenseLinearSystem sys;
	Eigen::MatrixXd Sigma;
	Eigen::MatrixXd block(const std::vector<VariableId>& group) const
	{
		std::vector<int> idx;
		for (VariableId v : group)
			for (size_t k = 0; k < order.size(); k++)
				if (order[k] == v)
					for (int c = sys.offsets[k]; c < sys.offsets[k + 1]; c++) idx.push_back(c);
		Eigen::MatrixXd B(idx.size(), idx.size());
		for (size_t i = 0; i < idx.size(); i++)
			for (size_t j = 0; j < idx.size(); j++) B(i, j) = Sigma(idx[i], idx[j]);
		return B;
	}
};

Dense dense_inverse(const CovarianceScene& s, bool pseudo)
{
	Dense d;
	for (const auto& [v, var] : s.problem.variables())
		if (!var.constant) d.order.push_back(v);
	d.sys = linearize_dense(s.problem, d.order);
	if (!pseudo)
		d.Sigma = d.sys.H.inverse();
	else
	{
		Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(d.sys.H);
		Eigen::VectorXd inv = es.eigenvalues();
		for (int i = 0; i < inv.size(); i++) inv[i] = i < 6 ? 0.0 : 1.0 / inv[i];  // the 6 gauge motions
		d.Sigma = es.eigenvectors() * inv.asDiagonal() * es.eigenvectors().transpose();
	}
	return d;
}

double relative_error(const Eigen::MatrixXd& got, const Eigen::MatrixXd& want)
{
	return (got - want).norm() / want.norm();
}

CovarianceRequest some_groups(const CovarianceScene& s)
{
	CovarianceRequest r;
	r.groups = {{s.poses[3]}, {s.points[5]}, {s.poses[1], s.points[2], s.poses[0]}, {s.points[0], s.points[11]}};
	return r;
}
}  // namespace

TEST(Covariance, BlocksEqualTheDenseInverseForEveryLinearSolver)
{
	for (auto type : {LinearSolverType::DenseSchur, LinearSolverType::SparseSchur, LinearSolverType::DenseNormal,
					  LinearSolverType::SparseNormal})
	{
		CovarianceScene s = make_covariance_scene(false);
		SolverOptions o;
		o.linear_solver = type;
		const CovarianceRequest req = some_groups(s);
		const CovarianceResult c = marginal_covariance(s.problem, req, o);
		ASSERT_TRUE(c.ok) << c.message;
		const Dense d = dense_inverse(s, false);
		for (size_t g = 0; g < req.groups.size(); g++)
		{
			std::vector<VariableId> free_vars;
			for (VariableId v : req.groups[g])
				if (!s.problem.is_constant(v)) free_vars.push_back(v);
			const Eigen::MatrixXd want = d.block(free_vars);
			// The constant pose 0 (last in group 2) has zero rows and columns.
			const Eigen::MatrixXd got = c.blocks[g].topLeftCorner(want.rows(), want.cols());
			EXPECT_LT(relative_error(got, want), 1e-9) << to_string(type) << " group " << g;
			EXPECT_NEAR(c.blocks[g].norm(), got.norm(), 1e-15 * got.norm()) << to_string(type) << " group " << g;
		}
		EXPECT_GT(c.solves, 0);
	}
}

TEST(Covariance, ASolveRecoversThemAtItsSolutionFromItsLastLinearisation)
{
	CovarianceScene s = make_covariance_scene(false);
	SolverOptions o;
	o.function_tolerance = 1e-14;
	const CovarianceRequest req = some_groups(s);
	CovarianceResult in_solve;
	const Summary sum = solve(s.problem, o, req, &in_solve);
	ASSERT_TRUE(sum.is_solution_usable());
	ASSERT_TRUE(in_solve.ok) << in_solve.message;
	const CovarianceResult after = marginal_covariance(s.problem, req, o);
	for (size_t g = 0; g < req.groups.size(); g++)
		EXPECT_LT(relative_error(in_solve.blocks[g], after.blocks[g]), 1e-12) << "group " << g;
}

TEST(Covariance, SingularSystemIsReportedNotInverted)
{
	CovarianceScene s = make_covariance_scene(true);
	const CovarianceResult c = marginal_covariance(s.problem, some_groups(s));
	EXPECT_FALSE(c.ok);
	EXPECT_TRUE(c.blocks.empty());
}

TEST(Covariance, MinimumNormGaugeEqualsThePseudoInverse)
{
	CovarianceScene s = make_covariance_scene(true);
	const Dense d = dense_inverse(s, true);  // H⁺ of the free problem
	CovarianceRequest req = some_groups(s);
	// The six global motions p ↦ p + u + w × p in each variable's tangent coordinates.
	for (VariableId v : s.poses)
	{
		const auto T = se3_view(s.problem.value(v));
		const Eigen::Matrix3d Rt = T.leftCols<3>().transpose();
		Eigen::MatrixXd B = Eigen::MatrixXd::Zero(6, 6);
		B.block<3, 3>(0, 0) = Rt;
		B.block<3, 3>(0, 3) = -Rt * skew(T.col(3));
		B.block<3, 3>(3, 3) = Rt;
		req.gauge[v] = B;
	}
	for (VariableId v : s.points)
	{
		Eigen::MatrixXd B(3, 6);
		B << Eigen::Matrix3d::Identity(), -skew(Eigen::Map<const Eigen::Vector3d>(s.problem.value(v)));
		req.gauge[v] = B;
	}
	for (int held : {0, 2})  // any held pose gives the same minimum-norm covariance
	{
		CovarianceScene h = s;
		h.problem.set_constant(h.poses[held]);
		const CovarianceResult c = marginal_covariance(h.problem, req);
		ASSERT_TRUE(c.ok) << c.message;
		for (size_t g = 0; g < req.groups.size(); g++)
			EXPECT_LT(relative_error(c.blocks[g], d.block(req.groups[g])), 1e-9) << "held " << held << " group " << g;
	}
}

TEST(Covariance, ManyKeptBlocksFromTheSelectedInverseEqualTheDenseInverse)
{
	CovarianceScene s = make_chain_scene(16);
	CovarianceRequest req;
	for (std::size_t i = 1; i < s.poses.size(); i++) req.groups.push_back({s.poses[i]});  // 90 columns
	req.groups.push_back({s.poses[1], s.poses[15]});  // far apart: outside the factor's band, solved
	req.groups.push_back({s.poses[2], s.points[4]});  // an eliminated variable: solved
	const Dense d = dense_inverse(s, false);
	for (auto type : {LinearSolverType::SparseSchur, LinearSolverType::DenseSchur})
	{
		SolverOptions o;
		o.linear_solver = type;
		const CovarianceResult c = marginal_covariance(s.problem, req, o);
		ASSERT_TRUE(c.ok) << c.message;
		for (std::size_t g = 0; g < req.groups.size(); g++)
			EXPECT_LT(relative_error(c.blocks[g], d.block(req.groups[g])), 1e-9) << to_string(type) << " group " << g;
		// CHOLMOD's factor serves the single poses (and the far pair if its supernodes happen to hold it);
		// the dense back end solves every column.
		if (type == LinearSolverType::SparseSchur)
			EXPECT_LE(c.solves, 21);
		else
			EXPECT_EQ(c.solves, 90 + 12 + 9);
	}
}
