// Data association: the individual-compatibility gate, JCBB against nearest neighbour, the quality
// measure, and the window on mrpt-common's rawlog without landmark IDs.
#include <swba/estimators/association_quality.h>
#include <swba/estimators/data_association.h>
#include <swba/estimators/ekf_slam.h>
#include <swba/estimators/sliding_window.h>
#include <swba/eval/trajectory.h>
#include <swba/io/rawlog.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

namespace
{
using swba::estimators::AssociationProblem;
using swba::estimators::DataAssociation;

/** One 2D prediction at the origin with covariance σ²·I and one reading `offset_sigmas`·σ away along x
 * (reading noise negligible). */
AssociationProblem one_pair(double offset_sigmas)
{
	const double sigma = 0.1;
	AssociationProblem p;
	p.dim = 2;
	p.predictions = {Eigen::Vector2d(0, 0)};
	p.prediction_covariance = sigma * sigma * Eigen::Matrix2d::Identity();
	p.readings = {Eigen::Vector2d(offset_sigmas * sigma, 0)};
	p.reading_covariances = {1e-12 * Eigen::Matrix2d::Identity()};
	return p;
}

TEST(DataAssociation, GateRejectsAReadingFourSigmaOffAndAcceptsOneSigmaOff)
{
	for (DataAssociation m : {DataAssociation::NearestNeighbour, DataAssociation::Jcbb})
	{
		// χ²₂(0.999) = 13.8: 1σ (d² = 1) passes, 4σ (d² = 16) does not.
		EXPECT_EQ(swba::estimators::associate(one_pair(1.0), m, 0.999), std::vector<int>{0});
		EXPECT_EQ(swba::estimators::associate(one_pair(4.0), m, 0.999), std::vector<int>{-1});
	}
	EXPECT_NEAR(swba::estimators::association_distance(one_pair(4.0), 0, 0), 16.0, 1e-6);
}

/** Two landmarks 1 m apart along x whose predictions share a large x uncertainty (the robot's), and
 * two readings both shifted by +0.6 m: reading 0 lies nearest landmark 1 alone, but only the pairing
 * (0 → 0, 1 → 1) is jointly compatible (one common shift). */
AssociationProblem ambiguous_pair()
{
	AssociationProblem p;
	p.dim = 2;
	p.predictions = {Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 0)};
	p.prediction_covariance = Eigen::MatrixXd::Zero(4, 4);
	const double s2 = 0.5 * 0.5;  // shared robot x uncertainty
	p.prediction_covariance(0, 0) = p.prediction_covariance(2, 2) = p.prediction_covariance(0, 2) =
		p.prediction_covariance(2, 0) = s2;
	p.prediction_covariance(1, 1) = p.prediction_covariance(3, 3) = 0.01 * 0.01;
	p.readings = {Eigen::Vector2d(0.6, 0), Eigen::Vector2d(1.6, 0)};
	p.reading_covariances = {0.01 * 0.01 * Eigen::Matrix2d::Identity(), 0.01 * 0.01 * Eigen::Matrix2d::Identity()};
	return p;
}

TEST(DataAssociation, JcbbResolvesAnAmbiguousPairThatNearestNeighbourGetsWrong)
{
	const AssociationProblem p = ambiguous_pair();
	const std::vector<int> nn = swba::estimators::associate(p, DataAssociation::NearestNeighbour, 0.99);
	const std::vector<int> jcbb = swba::estimators::associate(p, DataAssociation::Jcbb, 0.99);
	EXPECT_EQ(jcbb, (std::vector<int>{0, 1}));
	EXPECT_NE(nn, (std::vector<int>{0, 1})) << "nearest neighbour should take landmark 1 for reading 0";
	EXPECT_EQ(nn[0], 1);
}

/** Two 2D predictions `gap` apart along x, independent, each with covariance σ²·I (σ = 0.1), and
 * readings at `xs` on the x axis (reading noise negligible). */
AssociationProblem two_landmarks(double gap, const std::vector<double>& xs)
{
	AssociationProblem p;
	p.dim = 2;
	p.predictions = {Eigen::Vector2d(0, 0), Eigen::Vector2d(gap, 0)};
	p.prediction_covariance = 0.01 * Eigen::MatrixXd::Identity(4, 4);
	for (double x : xs)
	{
		p.readings.push_back(Eigen::Vector2d(x, 0));
		p.reading_covariances.push_back(1e-12 * Eigen::Matrix2d::Identity());
	}
	return p;
}

TEST(DataAssociation, JcbbGivesALoneReadingItsNearestCompatibleLandmark)
{
	// The reading is inside both gates (d² 4.84 and 0.64 against χ²₂(0.99) = 9.21), nearer the second
	// landmark. (MRPT 2.5's JCBB keeps the first compatible one, landmark 0.)
	const AssociationProblem p = two_landmarks(0.3, {0.22});
	EXPECT_EQ(swba::estimators::associate(p, DataAssociation::Jcbb, 0.99), std::vector<int>{1});
	EXPECT_EQ(swba::estimators::associate(p, DataAssociation::NearestNeighbour, 0.99), std::vector<int>{1});
}

TEST(DataAssociation, JcbbLeavesOutAPairingThatIsNotJointlyCompatible)
{
	// Each reading is individually compatible with its landmark (d² 7.29 and 8.41 < 9.21), but the two
	// together are not (15.7 > χ²₄(0.99) = 13.28): JCBB pairs only the nearer one; nearest neighbour,
	// which tests readings one by one, pairs both.
	const AssociationProblem p = two_landmarks(10, {0.27, 10.29});
	EXPECT_EQ(swba::estimators::associate(p, DataAssociation::Jcbb, 0.99), (std::vector<int>{0, -1}));
	EXPECT_EQ(swba::estimators::associate(p, DataAssociation::NearestNeighbour, 0.99), (std::vector<int>{0, 1}));
}

TEST(DataAssociation, JcbbSearchStopsAtItsBudgetWithAFullPairing)
{
	// Twelve readings and twelve landmarks at one point: every pairing is jointly compatible and the 12!
	// orders tie on pairs, so the search for the nearest cannot finish; it stops at its budget, says so,
	// and keeps the full pairing its first descent found.
	AssociationProblem p;
	p.dim = 2;
	const int n = 12;
	p.prediction_covariance = 0.01 * Eigen::MatrixXd::Identity(2 * n, 2 * n);
	for (int i = 0; i < n; i++)
	{
		p.predictions.push_back(Eigen::Vector2d(0, 0));
		p.readings.push_back(Eigen::Vector2d(0.001 * i, 0));
		p.reading_covariances.push_back(1e-4 * Eigen::Matrix2d::Identity());
	}
	bool cut = false;
	const std::vector<int> a = swba::estimators::associate(p, DataAssociation::Jcbb, 0.99, &cut);
	EXPECT_TRUE(cut);
	std::vector<int> sorted = a;
	std::sort(sorted.begin(), sorted.end());
	for (int j = 0; j < n; j++) EXPECT_EQ(sorted[static_cast<std::size_t>(j)], j);  // each landmark once
	bool small_cut = true;
	swba::estimators::associate(two_landmarks(0.3, {0.22}), DataAssociation::Jcbb, 0.99, &small_cut);
	EXPECT_FALSE(small_cut);
}

TEST(AssociationQuality, CountsCorrectDuplicateAndSpuriousLandmarks)
{
	// True landmarks 7 and 8. Estimated 0 = 7 (3 readings), 1 = 7 again (2 readings: a duplicate),
	// 2 = one reading of each (a tie: stands for 7, spurious), 3 = 8 (one reading: not confirmed).
	const swba::estimators::ReadingIds truth = {{7, 7, 7}, {7, 7}, {7, 8}, {8}};
	const swba::estimators::ReadingIds assigned = {{0, 0, 0}, {1, 1}, {2, 2}, {3}};
	const auto q = swba::estimators::evaluate_association(assigned, truth);
	EXPECT_EQ(q.readings, 8u);
	EXPECT_EQ(q.landmarks, 3u);
	EXPECT_EQ(q.true_landmarks, 2u);
	EXPECT_EQ(q.associated, 7u);  // all but the unconfirmed one
	EXPECT_EQ(q.correct, 3u);     // only the primary of 7
	EXPECT_EQ(q.duplicates, 2u);  // 1 and 2 also stand for 7
	EXPECT_EQ(q.spurious, 0u);    // 2: one of two readings is from 7, not fewer than half
	const auto perfect = swba::estimators::evaluate_association(truth, truth);
	EXPECT_EQ(perfect.correct, perfect.associated);
	EXPECT_EQ(perfect.duplicates, 0u);
	EXPECT_DOUBLE_EQ(perfect.fraction_correct(), 1.0);
}

/** A step of a robot at (0, y) on the plane z = 0 reading the landmarks `marks` (ID, position), with
 * odometry σ `odometry_sigma` (MRPT's order: x, y, z, yaw, pitch, roll), range σ 1 cm, bearing σ 0.1°. */
swba::io::RawlogStep scene_step(std::size_t k, double y, const std::vector<std::pair<std::int32_t, Eigen::Vector2d>>& marks,
								const Eigen::Matrix<double, 6, 1>& odometry_sigma)
{
	swba::io::RawlogStep s;
	s.index = k;
	s.has_odometry = true;
	s.odometry.cov = Eigen::Matrix<double, 6, 6>(odometry_sigma.cwiseAbs2().asDiagonal());
	s.has_observation = true;
	s.sensor_std_range = 0.01;
	s.sensor_std_yaw = s.sensor_std_pitch = 0.1 * M_PI / 180;
	for (const auto& [id, p] : marks)
		s.readings.push_back({id, std::hypot(p.x(), p.y() - y), std::atan2(p.y() - y, p.x()), 0.0});
	return s;
}

/** A scene for re-association: landmarks A = (4, 0) and B = (4, 0.4), 0.4 m apart, and twenty more on
 * rings 6–10 m out, all on the plane z = 0. Steps 0–4: the robot stands at the origin (odometry σ 1 mm)
 * and sees all of them. Step 5: it moves 0.4 m to (0, −0.4) while the odometry reports no motion with
 * σ 0.3 m, and sees A (reading 0; not B) and the twenty: from the dead-reckoned pose, A's reading lies
 * exactly where B is predicted. Steps 6–7: it stands there (odometry σ 1 mm) and sees the twenty. */
swba::io::RawlogStep reassociation_step(std::size_t k)
{
	std::vector<std::pair<std::int32_t, Eigen::Vector2d>> marks;
	if (k <= 5) marks.push_back({1, {4.0, 0.0}});
	if (k < 5) marks.push_back({2, {4.0, 0.4}});
	for (int i = 0; i < 20; i++)
	{
		const double a = 2 * M_PI * i / 20 + 0.1, r = 6.0 + 2.0 * (i % 3);
		marks.push_back({10 + i, {r * std::cos(a), r * std::sin(a)}});
	}
	Eigen::Matrix<double, 6, 1> sigma = Eigen::Matrix<double, 6, 1>::Constant(1e-3);
	if (k == 5) sigma << 0.3, 0.3, 1e-3, 0.02, 1e-3, 1e-3;
	return scene_step(k, k < 5 ? 0.0 : -0.4, marks, sigma);
}

/** Runs the scene with `association` (and reassociate as given); returns the estimator after step 7. */
std::unique_ptr<swba::estimators::SlidingWindowEstimator> run_reassociation_scene(DataAssociation association,
																				  bool reassociate,
																				  int* reassociated_at_5 = nullptr)
{
	swba::estimators::SlidingWindowOptions o;
	o.window_size = 20;  // nothing is marginalised: the decisions stay open
	o.model = swba::estimators::PoseModel::Spatial;
	o.association = association;
	o.reassociate = reassociate;
	o.robust_loss = swba::RobustLoss::Cauchy;  // the readings' consensus, not a compromise with the wrong one
	auto est = std::make_unique<swba::estimators::SlidingWindowEstimator>(o);
	for (std::size_t k = 0; k < 8; k++)
	{
		const int moved = est->process(reassociation_step(k)).reassociated;
		if (k == 5 && reassociated_at_5) *reassociated_at_5 = moved;
	}
	return est;
}

TEST(WindowAssociation, AReadingGivenTheWrongLandmarkIsReassociatedAndTheEstimateIsTheKnownIdOne)
{
	// Nearest neighbour gives A's step-5 reading to B (where the dead-reckoned pose predicts it). The
	// step's solve (Cauchy loss) puts the pose at (0, −0.4) on the twenty other readings; there the
	// reading fails the gate against B (0.4 m off) and passes it against A: it is moved, and from the
	// next solve on the window holds the problem a run with the true IDs holds, so it reaches that run's
	// estimate. Without re-association the wrong reading stays, down-weighted, and still pulls the pose
	// and B a little. (Under least squares the wrong reading pulls the pose so far that it fits neither
	// landmark and the other readings' next associations fail: doc/association.md, "Re-association".)
	int moved = -1;
	const auto nn = run_reassociation_scene(DataAssociation::NearestNeighbour, true, &moved);
	const auto ids = run_reassociation_scene(DataAssociation::Ids, true);
	const auto kept = run_reassociation_scene(DataAssociation::NearestNeighbour, false);
	EXPECT_EQ(moved, 1);
	EXPECT_EQ(nn->reading_counts().reassociated, 1u);
	EXPECT_EQ(kept->reading_counts().reassociated, 0u);
	const auto assigned = nn->assigned_ids();
	EXPECT_EQ(assigned.at(5).at(0), assigned.at(0).at(0)) << "A's step-5 reading should end at A's landmark";
	EXPECT_EQ(kept->assigned_ids().at(5).at(0), kept->assigned_ids().at(0).at(1)) << "without it, B's landmark";

	const auto position_error = [](const swba::estimators::SlidingWindowEstimator& a,
								   const swba::estimators::SlidingWindowEstimator& b) {
		double worst = 0;
		const auto pa = a.window_poses(), pb = b.window_poses();
		EXPECT_EQ(pa.size(), pb.size());
		for (std::size_t i = 0; i < std::min(pa.size(), pb.size()); i++)
			worst = std::max(worst, (pa[i].second.asVectorVal() - pb[i].second.asVectorVal()).norm());
		return worst;
	};
	EXPECT_LT(position_error(*nn, *ids), 1e-6);
	EXPECT_GT(position_error(*kept, *ids), 2e-5);  // measured 6.5e-5 m
	// Landmark B: as the ID run has it with re-association, pulled towards A's reading without.
	const auto b_of = [](const swba::estimators::SlidingWindowEstimator& e, std::int32_t id) {
		return e.landmarks().at(id);
	};
	EXPECT_LT((b_of(*nn, assigned.at(0).at(1)) - b_of(*ids, 2)).norm(), 1e-6);
	EXPECT_GT((b_of(*kept, kept->assigned_ids().at(0).at(1)) - b_of(*ids, 2)).norm(), 5e-5);  // measured 1.9e-4 m
	EXPECT_LT((b_of(*nn, assigned.at(0).at(0)) - b_of(*ids, 1)).norm(), 1e-6);  // A
}

/** A scene for the second test of unmatched readings: landmark A = (4, 0) seen from the origin on steps
 * 0–4 (odometry σ 1 mm). Step 5: the robot slips 0.5 m to (0, −0.5) while its odometry reports no motion
 * with σ 5 cm (overconfident: a 10σ error), and reads A and a landmark C = (4, 3) never seen before.
 * From the dead-reckoned pose A's reading is 0.5 m from A's prediction, whose σ is about 5 cm (d² ≈ 94,
 * outside the gate of 16.3); with the pose's covariance × 9 it is inside (d² ≈ 11); C's reading is 3 m
 * from A either way. */
swba::io::RawlogStep slip_step(std::size_t k)
{
	const double y = k < 5 ? 0.0 : -0.5;
	std::vector<std::pair<std::int32_t, Eigen::Vector2d>> marks = {{1, {4.0, 0.0}}};
	if (k == 5) marks.push_back({2, {4.0, 3.0}});
	Eigen::Matrix<double, 6, 1> sigma = Eigen::Matrix<double, 6, 1>::Constant(1e-3);
	if (k == 5) sigma.head<2>().setConstant(0.05);
	return scene_step(k, y, marks, sigma);
}

TEST(WindowAssociation, AReadingOfAKnownLandmarkOutsideItsGateIsMatchedWithThePoseInflatedNotANewLandmark)
{
	const auto run = [](double inflation) {
		swba::estimators::SlidingWindowOptions o;
		o.window_size = 20;
		o.model = swba::estimators::PoseModel::Spatial;
		o.association = DataAssociation::Jcbb;
		o.association_pose_inflation = inflation;
		auto est = std::make_unique<swba::estimators::SlidingWindowEstimator>(o);
		for (std::size_t k = 0; k < 6; k++) est->process(slip_step(k));
		return est;
	};
	const auto with = run(9.0), without = run(1.0);
	const auto a = with->assigned_ids(), b = without->assigned_ids();
	ASSERT_EQ(a.at(5).size(), 2u);
	EXPECT_EQ(a.at(5).at(0), a.at(0).at(0)) << "A's reading after the slip should be A's";
	EXPECT_NE(a.at(5).at(1), a.at(0).at(0)) << "C's reading should start its own landmark";
	EXPECT_EQ(with->reading_counts().rematched, 1u);
	EXPECT_NE(b.at(5).at(0), b.at(0).at(0)) << "without the second test A's reading starts a duplicate";
	EXPECT_EQ(without->reading_counts().rematched, 0u);
}

/** The true landmark of every reading of mrpt-common's kf-slam_6D_demo_DA (the simulator's files). */
swba::estimators::ReadingIds demo_da_truth(const swba::io::Rawlog& rawlog)
{
	const std::string ds = SWBA_MRPT_DATASETS;
	// Row k of the simulator's robot path: the pose of observation k.
	const auto path = swba::eval::read_mrpt_ground_truth(ds + "/kf-slam_6D_demo_DA_ground_truth_robot_path.txt").poses;
	return swba::estimators::true_landmarks_of_readings(
		rawlog, path, swba::estimators::read_landmark_ground_truth(ds + "/kf-slam_6D_demo_DA_ground_truth.txt"), 0.5);
}

TEST(WindowAssociation, MrptEkfAssociationsAreReportedAsItMadeThem)
{
	// MRPT's JCBB gets this rawlog right; what it did is read back per reading (a landmark index of its
	// map), so the quality measure sees all of its pairings right and no duplicate.
	swba::io::RawlogReaderOptions ro;
	ro.require_landmark_ids = false;
	const auto rawlog = swba::io::read_rawlog(std::string(SWBA_MRPT_DATASETS) + "/kf-slam_6D_demo_DA.rawlog", ro);
	swba::estimators::EkfSlamOptions eo;
	eo.data_association = "jcbb";
	const auto r = swba::estimators::run_ekf_slam(rawlog.steps, eo);
	ASSERT_FALSE(r.failed) << r.failure;
	ASSERT_EQ(r.assigned_ids.size(), rawlog.steps.size());
	const auto q = swba::estimators::evaluate_association(r.assigned_ids, demo_da_truth(rawlog));
	EXPECT_EQ(q.readings, rawlog.readings);
	EXPECT_GE(static_cast<double>(q.associated), 0.95 * static_cast<double>(q.readings));
	EXPECT_EQ(q.correct, q.associated);
	EXPECT_EQ(q.duplicates, 0u);
	EXPECT_EQ(q.landmarks, q.true_landmarks);
}

TEST(WindowAssociation, RawlogWithoutIdsIsAssociatedCorrectly)
{
	const std::string ds = SWBA_MRPT_DATASETS;
	swba::io::RawlogReaderOptions ro;
	ro.require_landmark_ids = false;
	const auto rawlog = swba::io::read_rawlog(ds + "/kf-slam_6D_demo_DA.rawlog", ro);
	swba::estimators::SlidingWindowOptions o;
	o.window_size = 10;
	swba::estimators::SlidingWindowEstimator est(o);
	for (const auto& s : rawlog.steps) est.process(s);
	est.finish();
	const auto truth = demo_da_truth(rawlog);
	const auto q = swba::estimators::evaluate_association(est.assigned_ids(), truth);
	EXPECT_EQ(q.readings, rawlog.readings);
	EXPECT_GE(q.fraction_correct(), 0.99);
	EXPECT_GE(static_cast<double>(q.associated), 0.99 * static_cast<double>(q.readings));
	EXPECT_EQ(q.duplicates, 0u);
	EXPECT_EQ(q.spurious, 0u);
	EXPECT_EQ(q.landmarks, q.true_landmarks);
}
}  // namespace
