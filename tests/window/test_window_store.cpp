// LandmarkStore alone (records, the variable index, the linear tail's reading counts, the readings
// dropped for good, the map), and the association's decisions on hand-made inputs: match_readings on
// a prediction, reassociation_moves on a table of gate distances.
#include <gtest/gtest.h>

#include "landmark_prediction.h"
#include "landmark_store.h"
#include "reassociation_moves.h"

#include <swba/core/manifold.h>
#include <swba/nonlinear/problem.h>

#include <cmath>
#include <map>
#include <set>
#include <vector>

using namespace swba;
using namespace swba::estimators;
using namespace swba::estimators::detail;

namespace
{
Observation store_reading(std::size_t step, FactorId factor = -1)
{
	return {step, {5, 0, 0}, {0.1, 0.01, 0.01}, factor};
}

Landmark store_landmark(std::int32_t id, VariableId var, std::vector<Observation> obs)
{
	Landmark lm;
	lm.id = id;
	lm.var = var;
	lm.obs = std::move(obs);
	return lm;
}

/** Re-association's inputs over `store` with gate distances from `table` (landmark ID, factor; absent:
 * far outside) and positions from `at`. */
using DistanceTable = std::map<std::pair<std::int32_t, FactorId>, double>;
ReassociationInputs store_reassociation(const LandmarkStore& store, const DistanceTable& table,
										const std::map<std::int32_t, Eigen::Vector3d>& at,
										const std::set<VariableId>& in_prior)
{
	return {store,
			[&table](const Landmark& lm, const Observation& o) {
				const auto it = table.find({lm.id, o.factor});
				return it == table.end() ? 1e6 : it->second;
			},
			[&at](const Landmark& lm) { return at.at(lm.id); },
			[&in_prior](VariableId v) { return in_prior.count(v) > 0; },
			7.8,
			3};
}
}  // namespace

TEST(LandmarkStore, FindsLandmarksByIdAndByVariable)
{
	LandmarkStore store;
	store.add(store_landmark(7, 100, {store_reading(1, 10)}));
	store.add(store_landmark(3, 101, {}));
	ASSERT_NE(store.find(7), nullptr);
	EXPECT_EQ(store.find(7)->var, 100);
	EXPECT_EQ(store.find(8), nullptr);
	EXPECT_TRUE(store.is_landmark(101));
	EXPECT_FALSE(store.is_landmark(102));
	ASSERT_NE(store.find_by_variable(101), nullptr);
	EXPECT_EQ(store.find_by_variable(101)->id, 3);
	std::vector<std::int32_t> order;
	for (const auto& [id, lm] : store) order.push_back(id);
	EXPECT_EQ(order, (std::vector<std::int32_t>{3, 7}));  // by ID

	store.rebind(store.at(7), 200);  // a new parameterisation
	EXPECT_FALSE(store.is_landmark(100));
	EXPECT_EQ(store.find_by_variable(200)->id, 7);

	store.at(7).held.push_back(store_reading(2));
	std::size_t held = 0;
	EXPECT_FALSE(store.forget(100, held));
	EXPECT_TRUE(store.forget(200, held));
	EXPECT_EQ(held, 1u);
	EXPECT_EQ(store.find(7), nullptr);
	EXPECT_EQ(store.size(), 1u);

	store.at(3).obs = {store_reading(1, 11), store_reading(2, 12)};
	store.forget_observations({11});
	ASSERT_EQ(store.at(3).obs.size(), 1u);
	EXPECT_EQ(store.at(3).obs.front().factor, 12);
}

TEST(LandmarkStore, LinearTailReadingsCountUntilReleased)
{
	LandmarkStore store;
	store.add(store_landmark(1, 100, {store_reading(1, 10), store_reading(1, 11), store_reading(2, 12)}));
	EXPECT_EQ(LandmarkStore::window_readings(store.at(1)), 3u);
	// Step 1 leaves the re-linearised poses: its two factors go, its readings still count.
	store.hold_tail_readings(1);
	store.forget_observations({10, 11});
	EXPECT_EQ(store.at(1).tail_readings, 2u);
	EXPECT_EQ(LandmarkStore::window_readings(store.at(1)), 3u);
	store.hold_tail_readings(2);
	store.forget_observations({12});
	EXPECT_EQ(LandmarkStore::window_readings(store.at(1)), 3u);
	store.release_tail_readings();  // step 1 leaves the window
	EXPECT_EQ(LandmarkStore::window_readings(store.at(1)), 1u);
	store.release_tail_readings();
	EXPECT_EQ(LandmarkStore::window_readings(store.at(1)), 0u);
	store.release_tail_readings();  // nothing left: no effect
	EXPECT_EQ(LandmarkStore::window_readings(store.at(1)), 0u);
}

TEST(LandmarkStore, DropsHeldAndUnconfirmedReadingsOfALeavingStep)
{
	LandmarkStore store;
	store.add(store_landmark(1, 100, {}));
	store.at(1).held = {store_reading(1), store_reading(2), store_reading(1)};
	store.waiting(5).push_back(store_reading(1));
	store.waiting(6).push_back(store_reading(1));
	store.waiting(6).push_back(store_reading(2));
	const LandmarkStore::Dropped at1 = store.drop_readings_at(1);
	EXPECT_EQ(at1.held, 2u);
	EXPECT_EQ(at1.unconfirmed, 2u);
	EXPECT_EQ(store.at(1).held.size(), 1u);
	EXPECT_EQ(store.find_waiting(5), nullptr);  // emptied lists go
	ASSERT_NE(store.find_waiting(6), nullptr);
	EXPECT_EQ(store.find_waiting(6)->size(), 1u);

	store.confirm(6);
	EXPECT_TRUE(store.unconfirmed().empty());
	store.waiting(9).push_back(store_reading(3));
	const LandmarkStore::Dropped rest = store.drop_pending();
	EXPECT_EQ(rest.held, 1u);
	EXPECT_EQ(rest.unconfirmed, 1u);
	EXPECT_TRUE(store.at(1).held.empty());
	EXPECT_TRUE(store.unconfirmed().empty());
}

TEST(LandmarkStore, MapKeepsAMarginalUntilTheLandmarkReturns)
{
	LandmarkStore store;
	EXPECT_FALSE(store.in_map(4));
	store.keep_in_map(4, {Eigen::Vector3d(1, 2, 3), Eigen::Matrix3d::Identity()});
	EXPECT_TRUE(store.in_map(4));
	EXPECT_EQ(store.map().size(), 1u);
	const MapLandmark m = store.take_from_map(4);
	EXPECT_EQ(m.position, Eigen::Vector3d(1, 2, 3));
	EXPECT_FALSE(store.in_map(4));
}

namespace
{
/** A joint prediction of two candidates at `a` and `b` in the sensor frame, each with its own noise
 * σ = 0.1 m only (no window variable). */
JointPrediction two_isolated_candidates(const Eigen::Vector3d& a, const Eigen::Vector3d& b)
{
	JointPrediction pred;
	pred.ok = true;
	pred.points = {a, b};
	pred.own.assign(2, 1e-2 * Eigen::MatrixXd::Identity(3, 3));
	pred.support.resize(2);
	return pred;
}
}  // namespace

TEST(MatchReadings, EachReadingTakesItsCompatibleCandidateOrNone)
{
	// Two candidates predicted at (5, 0, 0) and (0, 5, 0) in the sensor frame; readings of each (in
	// swapped order) and one of nothing.
	JointPrediction pred = two_isolated_candidates(Eigen::Vector3d(5, 0, 0), Eigen::Vector3d(0, 5, 0));
	const std::vector<std::pair<std::int32_t, Observation>> readings{
		{-1, {1, {5.02, M_PI / 2, 0}, {0.05, 0.005, 0.005}}},
		{-1, {1, {4.98, 0.01, 0}, {0.05, 0.005, 0.005}}},
		{-1, {1, {5, M_PI, 0}, {0.05, 0.005, 0.005}}}};
	for (DataAssociation method : {DataAssociation::NearestNeighbour, DataAssociation::Jcbb})
		EXPECT_EQ(match_readings(readings, pred, 2, method, 0.99, 3).target, (std::vector<int>{1, 0, -1}));
	// Planar rows (x, y) only: the same answer.
	pred.own.assign(2, 1e-2 * Eigen::MatrixXd::Identity(2, 2));
	EXPECT_EQ(match_readings(readings, pred, 2, DataAssociation::Jcbb, 0.99, 2).target, (std::vector<int>{1, 0, -1}));
}

TEST(MatchReadings, ListsEveryCompatibleCandidateNearestFirst)
{
	// Two candidates 0.2 m apart across the line of sight at 5 m: a reading
	// between them, nearer the second, is inside both gates (ambiguous on its own); one far off, in none.
	const JointPrediction pred = two_isolated_candidates(Eigen::Vector3d(5, 0, 0), Eigen::Vector3d(5, 0.2, 0));
	const std::vector<std::pair<std::int32_t, Observation>> readings{
		{-1, {1, {5, 0.028, 0}, {0.05, 0.005, 0.005}}}, {-1, {1, {5, -0.5, 0}, {0.05, 0.005, 0.005}}}};
	const ReadingMatch m = match_readings(readings, pred, 2, DataAssociation::NearestNeighbour, 0.99, 3);
	ASSERT_EQ(m.compatible.size(), 2u);
	EXPECT_EQ(m.compatible[0], (std::vector<int>{1, 0}));
	EXPECT_TRUE(m.compatible[1].empty());
	EXPECT_EQ(m.target, (std::vector<int>{1, -1}));
}

TEST(LandmarkPredictor, PredictionsKeepThePoseLandmarkCrossCovariances)
{
	// One pose at the origin and two world-point landmarks ahead of it; the group's covariance is dense
	// (the pose correlated with both landmarks, as after a stretch of dead reckoning). The predictions'
	// joint covariance must be J Σ Jᵀ with all of Σ, not with its diagonal only.
	Problem problem;
	const VariableId pose = problem.add_pose(mrpt::poses::CPose3D());
	const VariableId a = problem.add_variable(Eigen::Vector3d(5, 1, 0), euclidean_manifold(3));
	const VariableId b = problem.add_variable(Eigen::Vector3d(6, -1, 0.5), euclidean_manifold(3));
	const std::vector<PoseRecord> poses{{0.0, pose, mrpt::poses::CPose3D()}};
	const LandmarkPredictor predictor(problem, poses, PoseModel::Spatial, true);
	Landmark la = store_landmark(1, a, {}), lb = store_landmark(2, b, {});
	const std::vector<PredictionTarget> targets{{&la, nullptr}, {&lb, nullptr}};
	const LandmarkPredictor::Group g = predictor.group(0, targets);
	ASSERT_EQ(g.dim, 12);
	Eigen::MatrixXd A = Eigen::MatrixXd::Random(12, 12);
	CovarianceResult cov;
	cov.ok = true;
	cov.blocks.push_back(0.01 * (A * A.transpose() + Eigen::MatrixXd::Identity(12, 12)));
	const JointPrediction pred = predictor.predict(0, targets, g, cov);
	ASSERT_TRUE(pred.ok);
	const Eigen::MatrixXd J = pred.jacobian;
	const Eigen::MatrixXd expected = J.middleRows(0, 3) * cov.blocks.front() * J.middleRows(3, 3).transpose();
	EXPECT_LT((pred.covariance_of(0, 1, 3) - expected).norm(), 1e-9 * expected.norm());
	EXPECT_GT(expected.norm(), 1e-3);
}

TEST(ReassociationMoves, AMisfitReadingMovesToTheLandmarkItFits)
{
	LandmarkStore store;
	store.add(store_landmark(1, 100, {store_reading(1, 10), store_reading(2, 11)}));
	store.add(store_landmark(2, 101, {store_reading(3, 12), store_reading(4, 13)}));
	// Reading 13 is outside landmark 2's gate and inside landmark 1's, which has no reading of step 4.
	const DistanceTable d{{{1, 10}, 0.5}, {{1, 11}, 0.5}, {{2, 12}, 0.5}, {{2, 13}, 50.0}, {{1, 13}, 1.0}};
	const std::map<std::int32_t, Eigen::Vector3d> at{{1, Eigen::Vector3d(5, 0, 0)}, {2, Eigen::Vector3d(9, 0, 0)}};
	std::vector<ReadingMove> moves = reassociation_moves(store_reassociation(store, d, at, {}));
	ASSERT_EQ(moves.size(), 1u);
	EXPECT_EQ(moves[0].from, 2);
	EXPECT_EQ(moves[0].to, 1);
	EXPECT_EQ(moves[0].factor, 13);
	// Landmark 1 already has a reading of that step: a scan sees a landmark once.
	store.at(1).held.push_back(store_reading(4));
	EXPECT_TRUE(reassociation_moves(store_reassociation(store, d, at, {})).empty());
}

TEST(ReassociationMoves, ADuplicateMergesIntoTheOlderLandmarkUnlessInThePrior)
{
	LandmarkStore store;
	store.add(store_landmark(1, 100, {store_reading(1, 10)}));
	store.add(store_landmark(3, 102, {store_reading(5, 14)}));
	const DistanceTable d{{{1, 10}, 0.5}, {{3, 14}, 0.5}, {{1, 14}, 2.0}};
	const std::map<std::int32_t, Eigen::Vector3d> at{{1, Eigen::Vector3d(5, 0, 0)},
													 {3, Eigen::Vector3d(5.01, 0, 0)}};
	const std::vector<ReadingMove> moves = reassociation_moves(store_reassociation(store, d, at, {}));
	ASSERT_EQ(moves.size(), 1u);
	EXPECT_EQ(moves[0].from, 3);
	EXPECT_EQ(moves[0].to, 1);
	EXPECT_EQ(moves[0].factor, 14);
	EXPECT_TRUE(reassociation_moves(store_reassociation(store, d, at, {102})).empty());  // in the prior
	const std::map<std::int32_t, Eigen::Vector3d> far{{1, Eigen::Vector3d(5, 0, 0)}, {3, Eigen::Vector3d(8, 0, 0)}};
	EXPECT_TRUE(reassociation_moves(store_reassociation(store, d, far, {})).empty());  // out of reach
}
