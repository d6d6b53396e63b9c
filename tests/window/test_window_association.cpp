// Data association: the individual-compatibility gate, JCBB against nearest neighbour, the quality
// measure, and the window on mrpt-common's rawlog without landmark IDs.
#include <swba/estimators/association_quality.h>
#include <swba/estimators/data_association.h>
#include <swba/estimators/sliding_window.h>
#include <swba/io/rawlog.h>

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

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
	const auto path = [&] {
		std::vector<mrpt::poses::CPose3D> p;
		// The robot path of the simulator (row k = pose of observation k).
		std::ifstream f(ds + "/kf-slam_6D_demo_DA_ground_truth_robot_path.txt");
		std::string line;
		while (std::getline(f, line))
		{
			if (line.empty() || line[0] == '%') continue;
			std::istringstream in(line);
			double x, y, z, yaw, pitch, roll;
			if (in >> x >> y >> z >> yaw >> pitch >> roll) p.emplace_back(x, y, z, yaw, pitch, roll);
		}
		return p;
	}();
	const auto truth = swba::estimators::true_landmarks_of_readings(
		rawlog, path, swba::estimators::read_landmark_ground_truth(ds + "/kf-slam_6D_demo_DA_ground_truth.txt"), 0.5);
	const auto q = swba::estimators::evaluate_association(est.assigned_ids(), truth);
	EXPECT_EQ(q.readings, rawlog.readings);
	EXPECT_GE(q.fraction_correct(), 0.99);
	EXPECT_GE(static_cast<double>(q.associated), 0.99 * static_cast<double>(q.readings));
	EXPECT_EQ(q.duplicates, 0u);
	EXPECT_EQ(q.spurious, 0u);
	EXPECT_EQ(q.landmarks, q.true_landmarks);
}
}  // namespace
