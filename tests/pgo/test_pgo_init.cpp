// Pose-graph initialisation (swba/problems/pose_graph_init.h): chordal relaxation and odometry composition on synthetic
// graphs with a known truth (3D and 2D), LM from each start, the exact position step, and bad input.
#include <swba/io/g2o.h>
#include <swba/problems/pose_graph.h>
#include <swba/problems/pose_graph_init.h>
#include <swba/nonlinear/solver.h>

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <sstream>
#include <stdexcept>

namespace
{
using namespace swba::io;
using namespace swba::problems;

Eigen::Matrix<double, 6, 6> random_information6(std::mt19937& rng)
{
	std::uniform_real_distribution<double> u(-1.0, 1.0);
	Eigen::Matrix<double, 6, 6> A;
	for (int i = 0; i < 36; i++) A.data()[i] = u(rng);
	return 20.0 * (A * A.transpose() + 0.5 * Eigen::Matrix<double, 6, 6>::Identity());  // SPD, cross terms
}

Eigen::Quaterniond random_rotation(std::mt19937& rng)
{
	std::normal_distribution<double> n(0.0, 1.0);
	return Eigen::Quaterniond(n(rng), n(rng), n(rng), n(rng)).normalized();
}

Eigen::Quaterniond small_rotation(std::mt19937& rng, double sigma)
{
	std::normal_distribution<double> n(0.0, sigma);
	const Eigen::Vector3d w(n(rng), n(rng), n(rng));
	const double a = w.norm();
	return a > 0 ? Eigen::Quaterniond(Eigen::AngleAxisd(a, w / a)) : Eigen::Quaterniond::Identity();
}

/** Truth poses on a random walk (random orientations), odometry chain i→i+1 plus `loops` random loop
 * closures; edges measured from the truth with rotation/translation noise of the given sigmas.
 * Vertex values are the truth, then scrambled (except vertex 0) so that only the edges carry information. */
struct Synthetic3d
{
	PoseGraph truth, graph;
};
Synthetic3d make_synthetic3d(int n, int loops, double rot_sigma, double trans_sigma, unsigned seed)
{
	std::mt19937 rng(seed);
	std::normal_distribution<double> step(0.0, 1.0);
	Synthetic3d s;
	Eigen::Vector3d t = Eigen::Vector3d::Zero();
	for (int i = 0; i < n; i++)
	{
		PoseGraphVertex3 v;
		v.q = i == 0 ? Eigen::Quaterniond::Identity() : random_rotation(rng);
		v.t = t;
		t += Eigen::Vector3d(step(rng), step(rng), step(rng));
		s.truth.vertices3[i] = v;
	}
	std::vector<std::pair<int, int>> pairs;
	for (int i = 0; i + 1 < n; i++) pairs.emplace_back(i, i + 1);
	std::uniform_int_distribution<int> pick(0, n - 1);
	for (int k = 0; k < loops;)
	{
		const int a = pick(rng), b = pick(rng);
		if (std::abs(a - b) < 2) continue;
		pairs.emplace_back(a, b);
		k++;
	}
	std::normal_distribution<double> tn(0.0, trans_sigma);
	for (const auto& [a, b] : pairs)
	{
		const auto& va = s.truth.vertices3.at(a);
		const auto& vb = s.truth.vertices3.at(b);
		PoseGraphEdge3 e;
		e.from = a, e.to = b;
		e.q = ((va.q.conjugate() * vb.q) * small_rotation(rng, rot_sigma)).normalized();
		e.t = va.q.conjugate() * (vb.t - va.t) + Eigen::Vector3d(tn(rng), tn(rng), tn(rng));
		e.information = random_information6(rng);
		s.truth.edges3.push_back(e);
	}
	s.graph = s.truth;
	for (auto& [id, v] : s.graph.vertices3)
		if (id != 0)
		{
			v.q = random_rotation(rng);
			v.t = Eigen::Vector3d(step(rng), step(rng), step(rng));
		}
	return s;
}

double rotation_angle(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b)
{
	return Eigen::AngleAxisd(a.conjugate() * b).angle();
}

double mean_rotation_error(const PoseGraph& est, const PoseGraph& truth)
{
	double sum = 0;
	for (const auto& [id, v] : truth.vertices3) sum += rotation_angle(est.vertices3.at(id).q, v.q);
	return sum / truth.vertices3.size();
}

swba::SolverOptions tight_pgo_options()
{
	swba::SolverOptions o = pose_graph_solver_options();  // as swba pgo, with tight tolerances
	o.function_tolerance = 1e-15;
	o.gradient_tolerance = 1e-14;
	o.parameter_tolerance = 1e-14;
	return o;
}

double solve_from(PoseGraph g, PoseGraphInit init)
{
	PoseGraphInitOptions init_options;
	init_options.method = init;
	initialize_pose_graph(g, init_options);
	auto pp = build_pose_graph_problem(g);
	const auto summary = swba::solve(pp.problem, tight_pgo_options());
	EXPECT_TRUE(summary.is_solution_usable()) << summary.message;
	update_pose_graph(g, pp);
	return pose_graph_cost(g);
}

TEST(PgoInit, ParseNames)
{
	EXPECT_EQ(parse_pose_graph_init("chordal"), PoseGraphInit::Chordal);
	EXPECT_EQ(parse_pose_graph_init("odometry"), PoseGraphInit::Odometry);
	EXPECT_EQ(parse_pose_graph_init("file"), PoseGraphInit::File);
	EXPECT_THROW(parse_pose_graph_init("spanning"), std::invalid_argument);
	EXPECT_EQ(PoseGraphInitOptions{}.method, PoseGraphInit::Chordal);
}

TEST(PgoInit, ChordalRecoversNoiselessGraph3d)
{
	const auto s = make_synthetic3d(60, 40, 0.0, 0.0, 3);
	PoseGraph g = s.graph;
	ASSERT_GT(pose_graph_cost(g), 1.0);  // the scrambled start is far from the truth
	const auto summary = initialize_pose_graph(g);
	EXPECT_EQ(summary.method, PoseGraphInit::Chordal);
	EXPECT_EQ(summary.num_components, 1);
	EXPECT_EQ(summary.num_anchors, 1);
	EXPECT_EQ(summary.extra_anchors, 0);
	for (const auto& [id, v] : s.truth.vertices3)
	{
		const auto& e = g.vertices3.at(id);
		EXPECT_LT((e.q.toRotationMatrix() - v.q.toRotationMatrix()).cwiseAbs().maxCoeff(), 1e-9) << "vertex " << id;
		EXPECT_LT((e.t - v.t).norm(), 1e-9 * (1.0 + v.t.norm())) << "vertex " << id;
	}
	EXPECT_LT(pose_graph_cost(g), 1e-15);
}

TEST(PgoInit, OdometryRecoversNoiselessGraph3d)
{
	const auto s = make_synthetic3d(40, 20, 0.0, 0.0, 4);
	PoseGraph g = s.graph;
	PoseGraphInitOptions o;
	o.method = PoseGraphInit::Odometry;
	initialize_pose_graph(g, o);
	for (const auto& [id, v] : s.truth.vertices3)
	{
		EXPECT_LT(rotation_angle(g.vertices3.at(id).q, v.q), 1e-9) << "vertex " << id;
		EXPECT_LT((g.vertices3.at(id).t - v.t).norm(), 1e-9 * (1.0 + v.t.norm())) << "vertex " << id;
	}
}

TEST(PgoInit, FileKeepsValues)
{
	const auto s = make_synthetic3d(10, 5, 0.01, 0.01, 5);
	PoseGraph g = s.graph;
	PoseGraphInitOptions o;
	o.method = PoseGraphInit::File;
	initialize_pose_graph(g, o);
	for (const auto& [id, v] : s.graph.vertices3)
	{
		EXPECT_EQ(g.vertices3.at(id).t, v.t);
		EXPECT_EQ(g.vertices3.at(id).q.coeffs(), v.q.coeffs());
	}
}

TEST(PgoInit, ChordalRotationsBeatOdometryOnNoisyGraph3d)
{
	const auto s = make_synthetic3d(300, 150, 0.03, 0.05, 6);
	PoseGraph chordal = s.graph, odometry = s.graph;
	initialize_pose_graph(chordal);
	PoseGraphInitOptions o;
	o.method = PoseGraphInit::Odometry;
	initialize_pose_graph(odometry, o);
	const double e_chordal = mean_rotation_error(chordal, s.truth);
	const double e_odometry = mean_rotation_error(odometry, s.truth);
	EXPECT_LT(e_chordal, 0.5 * e_odometry) << "chordal " << e_chordal << " rad, odometry " << e_odometry << " rad";
	EXPECT_LT(pose_graph_cost(chordal), pose_graph_cost(odometry));
}

TEST(PgoInit, PositionsAreTheExactMinimiserGivenTheRotations)
{
	// With the rotations held, the cost is quadratic in the positions, cross terms Λ_tr included: the
	// chordal positions must zero its gradient (central differences, step 1e-5; quadratic ⇒ exact).
	for (const auto model : {swba::RotationError::G2o, swba::RotationError::CeresExample})
	{
		const auto s = make_synthetic3d(30, 20, 0.05, 0.1, 7);
		PoseGraph g = s.graph;
		PoseGraphInitOptions o;
		o.rotation_error = model;
		initialize_pose_graph(g, o);
		PoseGraph before = g;  // the same rotations, positions moved off the minimiser
		for (auto& [id, v] : before.vertices3)
			if (id != 0) v.t += Eigen::Vector3d(0.1, -0.05, 0.02) * static_cast<double>(id % 3 + 1);
		const auto max_position_gradient = [&](const PoseGraph& p) {
			const double h = 1e-5;
			double m = 0;
			for (const auto& [id, v] : p.vertices3)
				for (int k = 0; k < 3; k++)
				{
					PoseGraph plus = p, minus = p;
					plus.vertices3.at(id).t[k] += h;
					minus.vertices3.at(id).t[k] -= h;
					m = std::max(m, std::abs(pose_graph_cost(plus, model) - pose_graph_cost(minus, model)) / (2 * h));
				}
			return m;
		};
		const double max_gradient = max_position_gradient(g), max_gradient_before = max_position_gradient(before);
		ASSERT_GT(max_gradient_before, 1.0);
		EXPECT_LT(max_gradient, 1e-6 * max_gradient_before) << "model " << static_cast<int>(model);
	}
}

TEST(PgoInit, LmFromChordalReachesOdometryCostOrLower3d)
{
	const auto s = make_synthetic3d(150, 80, 0.05, 0.1, 8);
	const double c_chordal = solve_from(s.graph, PoseGraphInit::Chordal);
	const double c_odometry = solve_from(s.graph, PoseGraphInit::Odometry);
	EXPECT_LE(c_chordal, c_odometry * (1 + 1e-9)) << "chordal " << c_chordal << ", odometry " << c_odometry;
}

TEST(PgoInit, LmFromChordalReachesOdometryCostOrLowerOnShippedGraphs)
{
	for (const char* name : {"smallGrid3D", "intel"})
	{
		const PoseGraph g = read_g2o(std::string(SWBA_DATA_DIR) + "/posegraph/" + name + ".g2o");
		const double c_chordal = solve_from(g, PoseGraphInit::Chordal);
		const double c_odometry = solve_from(g, PoseGraphInit::Odometry);
		const double c_file = solve_from(g, PoseGraphInit::File);
		EXPECT_LE(c_chordal, c_odometry * (1 + 1e-9)) << name;
		EXPECT_LE(c_chordal, c_file * (1 + 1e-9)) << name;
	}
}

/** 2D truth: random walk with random headings, odometry chain and loop closures. */
PoseGraph make_synthetic2d(int n, int loops, double theta_sigma, unsigned seed, PoseGraph* truth_out)
{
	std::mt19937 rng(seed);
	std::normal_distribution<double> step(0.0, 1.0), noise(0.0, theta_sigma);
	std::uniform_real_distribution<double> heading(-M_PI, M_PI);
	PoseGraph truth;
	double x = 0, y = 0;
	for (int i = 0; i < n; i++)
	{
		truth.vertices2[i] = {x, y, i == 0 ? 0.0 : heading(rng)};
		x += step(rng), y += step(rng);
	}
	std::vector<std::pair<int, int>> pairs;
	for (int i = 0; i + 1 < n; i++) pairs.emplace_back(i, i + 1);
	std::uniform_int_distribution<int> pick(0, n - 1);
	for (int k = 0; k < loops;)
	{
		const int a = pick(rng), b = pick(rng);
		if (std::abs(a - b) < 2) continue;
		pairs.emplace_back(b, a);  // some edges point backwards
		k++;
	}
	for (const auto& [a, b] : pairs)
	{
		const auto& va = truth.vertices2.at(a);
		const auto& vb = truth.vertices2.at(b);
		PoseGraphEdge2 e;
		e.from = a, e.to = b;
		const double c = std::cos(va.theta), s = std::sin(va.theta);
		e.x = c * (vb.x - va.x) + s * (vb.y - va.y) + noise(rng);
		e.y = -s * (vb.x - va.x) + c * (vb.y - va.y) + noise(rng);
		e.theta = std::remainder(vb.theta - va.theta + noise(rng), 2 * M_PI);
		Eigen::Matrix3d A = Eigen::Matrix3d::Random();
		e.information = 10.0 * (A * A.transpose() + Eigen::Matrix3d::Identity());
		truth.edges2.push_back(e);
	}
	*truth_out = truth;
	PoseGraph g = truth;
	for (auto& [id, v] : g.vertices2)
		if (id != 0) v = {step(rng), step(rng), heading(rng)};
	return g;
}

TEST(PgoInit, ChordalRecoversNoiselessGraph2d)
{
	PoseGraph truth;
	PoseGraph g = make_synthetic2d(80, 40, 0.0, 9, &truth);
	initialize_pose_graph(g);
	for (const auto& [id, v] : truth.vertices2)
	{
		const auto& e = g.vertices2.at(id);
		EXPECT_LT(std::abs(std::remainder(e.theta - v.theta, 2 * M_PI)), 1e-9) << "vertex " << id;
		EXPECT_LT(std::hypot(e.x - v.x, e.y - v.y), 1e-9 * (1 + std::hypot(v.x, v.y))) << "vertex " << id;
	}
}

TEST(PgoInit, LmFromChordalReachesOdometryCostOrLower2d)
{
	PoseGraph truth;
	const PoseGraph g = make_synthetic2d(200, 80, 0.05, 10, &truth);
	const double c_chordal = solve_from(g, PoseGraphInit::Chordal);
	const double c_odometry = solve_from(g, PoseGraphInit::Odometry);
	EXPECT_LE(c_chordal, c_odometry * (1 + 1e-9));
}

TEST(PgoInit, DisconnectedGraphAndIsolatedVertexAreAnchoredAtTheirLowestId)
{
	// Component A = {0..19}, component B = {100..114} (noiseless, scrambled), isolated vertex 500.
	const auto a = make_synthetic3d(20, 10, 0.0, 0.0, 11);
	const auto b = make_synthetic3d(15, 8, 0.0, 0.0, 12);
	PoseGraph g = a.graph, truth = a.truth;
	std::mt19937 rng(13);
	const Eigen::Quaterniond qb = random_rotation(rng);
	const Eigen::Vector3d tb(5, -3, 2);
	for (const auto& [id, v] : b.graph.vertices3)
	{
		PoseGraphVertex3 w = v;
		if (id == 0) w.q = qb, w.t = tb;  // B's anchor: somewhere else than the origin
		g.vertices3[100 + id] = w;
		PoseGraphVertex3 tv = b.truth.vertices3.at(id);
		truth.vertices3[100 + id] = {tb + qb * tv.t, qb * tv.q};
	}
	for (auto e : b.graph.edges3)
	{
		e.from += 100, e.to += 100;
		g.edges3.push_back(e);
	}
	PoseGraphVertex3 lonely;
	lonely.t = Eigen::Vector3d(1, 2, 3);
	lonely.q = Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()));
	g.vertices3[500] = lonely;
	truth.vertices3[500] = lonely;

	for (const auto method : {PoseGraphInit::Chordal, PoseGraphInit::Odometry})
	{
		PoseGraph h = g;
		PoseGraphInitOptions o;
		o.method = method;
		PoseGraphInitSummary s;
		ASSERT_NO_THROW(s = initialize_pose_graph(h, o));
		EXPECT_EQ(s.num_components, 3);
		EXPECT_EQ(s.num_anchors, 3);
		EXPECT_EQ(s.extra_anchors, 2);
		for (const auto& [id, v] : truth.vertices3)
		{
			EXPECT_LT(rotation_angle(h.vertices3.at(id).q, v.q), 1e-9) << to_string(method) << " vertex " << id;
			EXPECT_LT((h.vertices3.at(id).t - v.t).norm(), 1e-9 * (1 + v.t.norm())) << to_string(method) << " vertex " << id;
		}
		// The whole pipeline runs; LM's damping carries the extra gauge freedom of component B.
		auto pp = build_pose_graph_problem(h);
		const auto summary = swba::solve(pp.problem, tight_pgo_options());
		EXPECT_TRUE(summary.is_solution_usable()) << summary.message;
	}
}

TEST(PgoInit, FixLinesAreAnchors)
{
	const auto s = make_synthetic3d(25, 10, 0.0, 0.0, 14);
	PoseGraph g = s.graph;
	g.fixed = {3, 7};
	g.vertices3.at(3) = s.truth.vertices3.at(3);
	g.vertices3.at(7) = s.truth.vertices3.at(7);
	const auto summary = initialize_pose_graph(g);
	EXPECT_EQ(summary.num_anchors, 2);
	EXPECT_EQ(summary.extra_anchors, 0);
	// Vertex 0 is not an anchor any more: it is recovered from the edges like the others.
	for (const auto& [id, v] : s.truth.vertices3)
		EXPECT_LT(rotation_angle(g.vertices3.at(id).q, v.q), 1e-9) << "vertex " << id;
}

TEST(PgoInit, EmptyGraphIsANoOp)
{
	PoseGraph g;
	const auto s = initialize_pose_graph(g);
	EXPECT_EQ(s.num_components, 0);
	EXPECT_EQ(g.num_vertices(), 0u);
}

// An information of 1e308 (finite, positive definite) overflows the chordal normal equations: the
// initial values would be NaN. An error naming the method and the vertex, never NaN handed on to LM.
TEST(PgoInit, NonFiniteInitialValuesAreAnErrorNamingTheMethodAndTheVertex)
{
	std::istringstream in("VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\nEDGE_SE2 0 1 2 0 0 1e308 0 0 1e308 0 1e308\n");
	PoseGraph g = read_g2o(in, "huge.g2o");
	try
	{
		initialize_pose_graph(g);
		ADD_FAILURE() << "no exception; vertex 1 = " << g.vertices2.at(1).x << " " << g.vertices2.at(1).y;
	}
	catch (const std::runtime_error& e)
	{
		const std::string msg = e.what();
		EXPECT_EQ(msg.rfind("chordal initialisation gave a non-finite value to vertex 1 (x y theta = ", 0), 0u) << msg;
	}
}
}  // namespace

namespace
{
/** `swba pgo`'s default pipeline (chordal start, pose_graph_solver_options) on the shipped graphs: final
 * cost within 1e-4 relative of Ceres's on the same model (Ceres 2.1 from the file's values, default
 * options; the figures of test_pgo_solve.cpp), and fewer LM iterations — i.e. fewer 6n factorisations,
 * the point of the initialisation — than the previous default (file values, initial trust region 1e4). */
TEST(PgoInit, DefaultPipelineMatchesCeresWithFewerIterations)
{
	struct Case
	{
		const char* file;
		swba::RotationError model;
		double ceres_final_cost;
	};
	const Case cases[] = {
		{"smallGrid3D.g2o", swba::RotationError::G2o, 512.6991351},
		{"parking-garage.g2o", swba::RotationError::CeresExample, 0.634190},
	};
	for (const auto& c : cases)
	{
		const PoseGraph input = read_g2o(std::string(SWBA_DATA_DIR) + "/posegraph/" + c.file);
		PoseGraphProblemOptions po;
		po.rotation_error = c.model;
		int iterations[2] = {0, 0};
		for (int run = 0; run < 2; run++)
		{
			PoseGraph g = input;
			swba::SolverOptions o = pose_graph_solver_options();
			if (run == 0)
			{
				PoseGraphInitOptions init_options;
				init_options.rotation_error = c.model;
				initialize_pose_graph(g, init_options);
			}
			else o.initial_trust_region_radius = 1e4;  // the previous default, from the file's values
			auto pp = build_pose_graph_problem(g, po);
			const auto summary = swba::solve(pp.problem, o);
			ASSERT_TRUE(summary.is_solution_usable()) << c.file;
			update_pose_graph(g, pp);
			const double cost = pose_graph_cost(g, c.model);
			EXPECT_NEAR(cost, summary.final_cost, 1e-9 * cost) << c.file << " run " << run;
			EXPECT_NEAR(cost / c.ceres_final_cost, 1.0, 1e-4) << c.file << " run " << run;
			iterations[run] = summary.iterations;
		}
		EXPECT_LT(iterations[0], iterations[1]) << c.file;
	}
}
}  // namespace
