// Pose-graph optimisation end to end in-process: a 4-pose loop with a known solution (3D and 2D,
// every gauge), robust kernels against an outlier, and the shipped graphs against Ceres's cost.
#include <swba/io/g2o.h>
#include <swba/problems/pose_graph.h>
#include <swba/nonlinear/gauge.h>
#include <swba/nonlinear/solver.h>

#include <gtest/gtest.h>

#include <random>

namespace
{
using namespace swba::io;
using namespace swba::problems;

Eigen::Matrix<double, 6, 6> random_information(std::mt19937& rng)
{
	std::uniform_real_distribution<double> u(-1.0, 1.0);
	Eigen::Matrix<double, 6, 6> A;
	for (int i = 0; i < 36; i++) A.data()[i] = u(rng);
	return 10.0 * (A * A.transpose() + Eigen::Matrix<double, 6, 6>::Identity());  // SPD, not diagonal
}

/** Truth: 4 poses on a rotated square, loop edges 0-1-2-3-0 plus the diagonal 0-2, all consistent. */
PoseGraph loop3d_truth()
{
	std::mt19937 rng(11);
	PoseGraph g;
	for (int i = 0; i < 4; i++)
	{
		PoseGraphVertex3 v;
		const double a = i * M_PI / 2;
		v.t = Eigen::Vector3d(2 * std::cos(a), 2 * std::sin(a), 0.3 * i);
		v.q = Eigen::AngleAxisd(a + 0.1 * i, Eigen::Vector3d(0.1 * i, 0.2, 1).normalized());
		g.vertices3[i] = v;
	}
	for (auto [a, b] : {std::pair{0, 1}, {1, 2}, {2, 3}, {3, 0}, {0, 2}})
	{
		PoseGraphEdge3 e;
		e.from = a, e.to = b;
		const auto &va = g.vertices3[a], &vb = g.vertices3[b];
		e.q = va.q.conjugate() * vb.q;
		e.t = va.q.conjugate() * (vb.t - va.t);
		e.information = random_information(rng);
		g.edges3.push_back(e);
	}
	return g;
}

void perturb(PoseGraph& g, bool including_first)
{
	std::mt19937 rng(5);
	std::uniform_real_distribution<double> u(-1.0, 1.0);
	for (auto& [id, v] : g.vertices3)
	{
		if (id == 0 && !including_first) continue;
		v.t += 0.3 * Eigen::Vector3d(u(rng), u(rng), u(rng));
		v.q = v.q * Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized()));
	}
	for (auto& [id, v] : g.vertices2)
	{
		if (id == 0 && !including_first) continue;
		v.x += 0.3 * u(rng), v.y += 0.3 * u(rng), v.theta += 0.3 * u(rng);
	}
}

swba::SolverOptions tight_options()
{
	swba::SolverOptions o;
	o.max_iterations = 100;
	o.function_tolerance = 1e-15;
	o.gradient_tolerance = 1e-14;
	o.parameter_tolerance = 1e-14;
	return o;
}

/** Largest translation / rotation difference of the relative poses T0⁻¹Ti (gauge-free). */
std::pair<double, double> relative_pose_error(const PoseGraph& a, const PoseGraph& b)
{
	double dt = 0, dr = 0;
	const auto& a0 = a.vertices3.at(0);
	const auto& b0 = b.vertices3.at(0);
	for (const auto& [id, va] : a.vertices3)
	{
		const auto& vb = b.vertices3.at(id);
		const Eigen::Vector3d ta = a0.q.conjugate() * (va.t - a0.t), tb = b0.q.conjugate() * (vb.t - b0.t);
		const Eigen::Quaterniond qa = a0.q.conjugate() * va.q, qb = b0.q.conjugate() * vb.q;
		dt = std::max(dt, (ta - tb).norm());
		dr = std::max(dr, qa.angularDistance(qb));
	}
	return {dt, dr};
}

TEST(PgoLoop3d, ZeroCostAtTruthAndRecoveredFromPerturbedStartWithEveryGauge)
{
	const PoseGraph truth = loop3d_truth();
	EXPECT_LT(pose_graph_cost(truth), 1e-25);
	for (auto gauge : {PoseGraphGauge::Fixed, PoseGraphGauge::Prior, PoseGraphGauge::Free})
	{
		PoseGraph g = truth;
		perturb(g, /*including_first=*/gauge == PoseGraphGauge::Free);
		const double initial = pose_graph_cost(g);
		EXPECT_GT(initial, 1.0);
		PoseGraphProblemOptions po;
		po.gauge = gauge;
		auto pp = build_pose_graph_problem(g, po);
		EXPECT_EQ(pp.num_constant, gauge == PoseGraphGauge::Fixed ? 1 : 0);
		EXPECT_EQ(pp.has_prior, gauge == PoseGraphGauge::Prior);
		const auto summary = swba::solve(pp.problem, tight_options());
		ASSERT_TRUE(summary.is_solution_usable()) << summary.full_report();
		EXPECT_NEAR(summary.initial_cost, initial, 1e-9 * initial);
		update_pose_graph(g, pp);
		EXPECT_LT(pose_graph_cost(g), 1e-16) << static_cast<int>(gauge);
		const auto [dt, dr] = relative_pose_error(g, truth);
		EXPECT_LT(dt, 1e-8) << static_cast<int>(gauge);
		EXPECT_LT(dr, 1e-8) << static_cast<int>(gauge);
		if (gauge != PoseGraphGauge::Free)  // the first pose stays where it was
		{
			EXPECT_LT((g.vertices3.at(0).t - truth.vertices3.at(0).t).norm(), 1e-8);
			EXPECT_LT(g.vertices3.at(3).q.angularDistance(truth.vertices3.at(3).q), 1e-8);
		}
	}
}

TEST(PgoLoop3d, FixLinesReplaceTheDefaultGauge)
{
	PoseGraph g = loop3d_truth();
	perturb(g, true);
	const auto v2 = g.vertices3.at(2);
	g.fixed = {2};
	auto pp = build_pose_graph_problem(g);
	EXPECT_EQ(pp.num_constant, 1);
	const auto summary = swba::solve(pp.problem, tight_options());
	ASSERT_TRUE(summary.is_solution_usable());
	update_pose_graph(g, pp);
	EXPECT_EQ(g.vertices3.at(2).t, v2.t);  // held exactly
	EXPECT_LT(pose_graph_cost(g), 1e-16);
	EXPECT_LT(relative_pose_error(g, loop3d_truth()).first, 1e-8);
}

TEST(PgoLoop3d, CauchyLossResistsAnOutlierEdge)
{
	const PoseGraph truth = loop3d_truth();
	PoseGraph g = truth;
	PoseGraphEdge3 bad;  // 1 → 3 measured 5 m off
	bad.from = 1, bad.to = 3;
	const auto &v1 = truth.vertices3.at(1), &v3 = truth.vertices3.at(3);
	bad.q = v1.q.conjugate() * v3.q;
	bad.t = v1.q.conjugate() * (v3.t - v1.t) + Eigen::Vector3d(5, 0, 0);
	bad.information = 10 * Eigen::Matrix<double, 6, 6>::Identity();
	g.edges3.push_back(bad);
	perturb(g, false);
	double err[2];
	for (int robust = 0; robust < 2; robust++)
	{
		PoseGraph h = g;
		PoseGraphProblemOptions po;
		if (robust) po.loss = swba::make_loss("cauchy", 1.0);
		auto pp = build_pose_graph_problem(h, po);
		ASSERT_TRUE(swba::solve(pp.problem, tight_options()).is_solution_usable());
		update_pose_graph(h, pp);
		err[robust] = relative_pose_error(h, truth).first;
	}
	EXPECT_GT(err[0], 0.1);            // least squares is pulled by the outlier
	EXPECT_LT(err[1], 0.1 * err[0]);   // Cauchy mostly ignores it
}

TEST(PgoLoop2d, RecoveredFromPerturbedStartAcrossTheAngleCut)
{
	PoseGraph truth;
	for (int i = 0; i < 4; i++)  // headings 3.0, −1.7, 1.9, −2.9: several edges cross ±π
		truth.vertices2[i] = {2 * std::cos(i * M_PI / 2), 2 * std::sin(i * M_PI / 2),
							  std::remainder(3.0 + 1.6 * i + 0.1 * i * i, 2 * M_PI)};
	for (auto [a, b] : {std::pair{0, 1}, {1, 2}, {2, 3}, {3, 0}, {0, 2}})
	{
		PoseGraphEdge2 e;
		e.from = a, e.to = b;
		const auto &va = truth.vertices2[a], &vb = truth.vertices2[b];
		const double c = std::cos(va.theta), s = std::sin(va.theta);
		e.x = c * (vb.x - va.x) + s * (vb.y - va.y);
		e.y = -s * (vb.x - va.x) + c * (vb.y - va.y);
		e.theta = std::remainder(vb.theta - va.theta, 2 * M_PI);
		e.information << 20, 2, 1, 2, 30, -1, 1, -1, 50;
		truth.edges2.push_back(e);
	}
	EXPECT_LT(pose_graph_cost(truth), 1e-25);
	PoseGraph g = truth;
	perturb(g, false);
	EXPECT_GT(pose_graph_cost(g), 1.0);
	auto pp = build_pose_graph_problem(g);
	ASSERT_TRUE(swba::solve(pp.problem, tight_options()).is_solution_usable());
	update_pose_graph(g, pp);
	EXPECT_LT(pose_graph_cost(g), 1e-16);
	for (const auto& [id, v] : g.vertices2)
	{
		const auto& t = truth.vertices2.at(id);
		EXPECT_NEAR(v.x, t.x, 1e-8);
		EXPECT_NEAR(v.y, t.y, 1e-8);
		EXPECT_NEAR(std::remainder(v.theta - t.theta, 2 * M_PI), 0.0, 1e-8);
		EXPECT_LE(std::abs(v.theta), M_PI);  // wrapped on the way back
	}
}
}  // namespace

namespace
{
struct ReferenceCase
{
	const char* file;
	swba::RotationError model;
	double ceres_final_cost;  // Ceres 2.1, SPARSE_NORMAL_CHOLESKY, same model, first pose fixed
	const char* source;
};

/** Solves a shipped graph with default options (first pose fixed) and compares the final cost with
 * Ceres's on the same model: within 1e-4 relative. */
TEST(PgoShippedGraphs, FinalCostsMatchCeresOnTheSameModel)
{
	const ReferenceCase cases[] = {
		{"smallGrid3D.g2o", swba::RotationError::G2o, 512.6991351, "bench/pgo, measured here"},
		{"sphere2500.g2o", swba::RotationError::CeresExample, 677.0087, "the quoted figure, doc/benchmarks/pgo.md"},
		{"sphere2500.g2o", swba::RotationError::G2o, 675.6080111, "bench/pgo, measured here"},
		// parking-garage (ceres model, 0.634190, the quoted figure) from the file's values with these options
		// but one thread: PgoInit.DefaultPipelineMatchesCeresWithFewerIterations, its second run (the thread
		// count changes no figure: apps.cli.threads_give_identical_output).
	};
	for (const auto& c : cases)
	{
		PoseGraph g = read_g2o(std::string(SWBA_DATA_DIR) + "/posegraph/" + c.file);
		PoseGraphProblemOptions po;
		po.rotation_error = c.model;
		auto pp = build_pose_graph_problem(g, po);
		swba::SolverOptions o;
		o.max_iterations = 100;
		o.num_threads = 2;
		const auto summary = swba::solve(pp.problem, o);
		ASSERT_TRUE(summary.is_solution_usable()) << c.file;
		update_pose_graph(g, pp);
		const double cost = pose_graph_cost(g, c.model);
		EXPECT_NEAR(cost, summary.final_cost, 1e-9 * cost) << c.file;
		EXPECT_NEAR(cost / c.ceres_final_cost, 1.0, 1e-4)
			<< c.file << " model " << static_cast<int>(c.model) << " (reference: " << c.source << ")";
	}
}
}  // namespace

TEST(PgoOptions, GaugeIsSpelledFixedLikeEveryOtherGaugeAndFixIsAccepted)
{
	using swba::problems::PoseGraphGauge;
	EXPECT_EQ(swba::problems::parse_pose_graph_gauge("fixed"), PoseGraphGauge::Fixed);
	EXPECT_EQ(swba::problems::parse_pose_graph_gauge("fix"), PoseGraphGauge::Fixed);
	EXPECT_EQ(swba::problems::to_string(PoseGraphGauge::Fixed), "fixed");
	EXPECT_EQ(swba::problems::to_string(PoseGraphGauge::Fixed), swba::to_string(swba::GaugeMode::Fixed));
	EXPECT_THROW(swba::problems::parse_pose_graph_gauge("loose"), std::invalid_argument);
}
