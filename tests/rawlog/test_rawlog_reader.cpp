// Reader of MRPT rawlogs: the kf-slam demos and malformed inputs.
#include <swba/eval/trajectory.h>
#include <swba/io/rawlog.h>

#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/obs/CActionRobotMovement3D.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/poses/Lie/SO.h>
#include <mrpt/serialization/CArchive.h>

#include <gtest/gtest.h>

#include "rawlog_test_data.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <set>

namespace
{
namespace fs = std::filesystem;
using swba::io::RawlogReaderOptions;
using swba::io::read_rawlog;


/** The poses of an MRPT ground-truth robot path (row i = true pose at SF_i). */
std::vector<mrpt::poses::CPose3D> ground_truth_poses(const std::string& path)
{
	return swba::eval::read_mrpt_ground_truth(path).poses;
}

/** A fresh temporary directory per test. */
fs::path temp_dir()
{
	const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
	fs::path d = fs::temp_directory_path() / (std::string("swba_rawlog_") + info->test_suite_name() + "_" + info->name());
	fs::remove_all(d);
	fs::create_directories(d);
	return d;
}

std::string expect_error(const std::string& path, const RawlogReaderOptions& opt = {})
{
	try
	{
		read_rawlog(path, opt);
	}
	catch (const std::runtime_error& e)
	{
		return e.what();
	}
	ADD_FAILURE() << "no exception reading " << path;
	return {};
}

/** Builds a small synthetic rawlog (SF0, AC0, SF1, AC1, ...). */
struct SynthOptions
{
	int steps = 5;
	bool odometry = true;
	bool bearing_range = true;
	int32_t id_offset = 1;	// landmark IDs: id_offset + i (negative → unknown)
	double bad_range = 1.0;	 // range of reading 1 of step 2
	double bad_yaw = 0.1;
	/** validCovariances with reading j's covariance diag(0.01, 1e-4, 4e-4)·(j + 1)² (σ 0.1, 0.01, 0.02
	 * times j + 1); `correlated`: range and yaw correlated in step 3's second reading. */
	bool own_covariance = false;
	bool correlated = false;
	double bad_range_variance = 0.01;  ///< range variance of reading 1 of step 2 (× 4), with own_covariance
};

void write_synth(const std::string& path, const SynthOptions& so, bool gz = true)
{
	std::unique_ptr<mrpt::io::CStream> out;
	if (gz)
		out = std::make_unique<mrpt::io::CFileGZOutputStream>(path);
	else
		out = std::make_unique<mrpt::io::CFileOutputStream>(path);
	auto arch = mrpt::serialization::archiveFrom(*out);
	for (int i = 0; i <= so.steps; i++)
	{
		mrpt::obs::CSensoryFrame sf;
		if (so.bearing_range)
		{
			auto obs = mrpt::obs::CObservationBearingRange::Create();
			obs->sensor_std_range = 0.01f;
			obs->sensor_std_yaw = 0.002f;
			obs->sensor_std_pitch = 0.002f;
			obs->sensorLocationOnRobot = mrpt::poses::CPose3D(0.1, 0, 0, 0, 0, 0);
			obs->validCovariances = so.own_covariance;
			for (int j = 0; j < 3; j++)
			{
				mrpt::obs::CObservationBearingRange::TMeasurement m;
				m.landmarkID = so.id_offset + j;
				m.range = (i == 2 && j == 1) ? float(so.bad_range) : 2.0f + float(j);
				m.yaw = (i == 2 && j == 1) ? float(so.bad_yaw) : 0.1f * float(j);
				m.pitch = 0.0f;
				const double f = (j + 1.0) * (j + 1.0);
				m.covariance.setZero();
				m.covariance(0, 0) = (i == 2 && j == 1 ? so.bad_range_variance : 0.01) * f;
				m.covariance(1, 1) = 1e-4 * f;
				m.covariance(2, 2) = 4e-4 * f;
				if (so.correlated && i == 4 && j == 1) m.covariance(0, 1) = m.covariance(1, 0) = 1e-4;
				obs->sensedData.push_back(m);
			}
			sf.insert(obs);
		}
		arch << sf;
		mrpt::obs::CActionCollection acts;
		if (so.odometry)
		{
			mrpt::obs::CActionRobotMovement3D act;
			act.poseChange.mean = mrpt::poses::CPose3D(0.2, 0, 0, 0.05, 0, 0);
			act.poseChange.cov.setIdentity();
			act.poseChange.cov *= 1e-4;
			acts.insert(act);
		}
		arch << acts;
	}
}

std::string read_bytes(const std::string& path)
{
	std::ifstream f(path, std::ios::binary);
	return std::string(std::istreambuf_iterator<char>(f), {});
}
void write_bytes(const std::string& path, const std::string& bytes)
{
	std::ofstream f(path, std::ios::binary);
	f.write(bytes.data(), std::streamsize(bytes.size()));
}
}  // namespace

TEST(RawlogReader, Kfslam6dDemoStepsObservationsSensor)
{
	const auto log = read_rawlog(kDatasets + "/kf-slam_6D_demo.rawlog");
	ASSERT_EQ(log.steps.size(), 599u);
	EXPECT_EQ(log.steps_with_odometry, 599u);
	EXPECT_EQ(log.steps_with_2d_odometry, 0u);
	EXPECT_EQ(log.skipped_readings, 0u);
	EXPECT_FALSE(log.truncated);
	EXPECT_EQ(log.entries, 1200u);	// SF0, AC0, …, SF599, AC599
	EXPECT_EQ(log.ignored_entries, 2u);	 // leading SF0 and trailing AC599
	EXPECT_GT(log.readings, 599u);
	EXPECT_EQ(log.distinct_landmarks, 48u);  // 50 simulated (simul_landmarks_demo_EKF-SLAM_in_6D.ini), 48 ever seen
	std::size_t sum = 0;
	for (std::size_t k = 0; k < log.steps.size(); k++)
	{
		const auto& s = log.steps[k];
		EXPECT_EQ(s.index, k);
		EXPECT_DOUBLE_EQ(s.time(), double(k + 1));
		EXPECT_EQ(s.frame_entry, 2 * k + 2);
		EXPECT_TRUE(s.actions && s.observations);
		sum += s.readings.size();
		for (const auto& r : s.readings)
		{
			EXPECT_GT(r.range, 0.0);
			EXPECT_LE(r.range, 10.0 + 1e-3);
			EXPECT_GE(r.landmark_id, 0);
		}
	}
	EXPECT_EQ(sum, log.readings);
	const auto& s = log.steps[100];
	EXPECT_TRUE(s.has_observation);
	for (int i = 0; i < 6; i++) EXPECT_EQ(s.sensor_pose[i], 0.0);
	EXPECT_NEAR(s.sensor_std_range, 0.01, 1e-7);
	EXPECT_NEAR(s.sensor_std_yaw, mrpt::DEG2RAD(0.1), 1e-7);
	EXPECT_NEAR(s.sensor_std_pitch, mrpt::DEG2RAD(0.1), 1e-7);
	// Odometry covariance as in REFERENCE.md: diag 0.06² ×3, (0.1°)² ×3; the first 4 steps do not move.
	EXPECT_NEAR(s.odometry.cov(0, 0), 0.06 * 0.06, 1e-8);
	EXPECT_NEAR(s.odometry.cov(3, 3), std::pow(mrpt::DEG2RAD(0.1), 2), 1e-10);
	EXPECT_EQ(s.odometry.cov(0, 1), 0.0);
	EXPECT_LT(log.steps[0].odometry.mean.norm(), 0.2);
	EXPECT_GT(log.steps[10].odometry.mean.norm(), 0.1);
}

TEST(RawlogReader, MaxStepsStopsEarly)
{
	RawlogReaderOptions opt;
	opt.max_steps = 10;
	const auto log = read_rawlog(kDatasets + "/kf-slam_6D_demo.rawlog", opt);
	EXPECT_EQ(log.steps.size(), 10u);
}

TEST(RawlogReader, Kfslam2dDemoOdometryLifted)
{
	const auto log = read_rawlog(kDatasets + "/kf-slam_demo.rawlog");
	ASSERT_EQ(log.steps.size(), 249u);
	EXPECT_EQ(log.steps_with_odometry, 249u);
	EXPECT_EQ(log.steps_with_2d_odometry, 249u);
	bool moved = false;
	for (const auto& s : log.steps)
	{
		EXPECT_TRUE(s.odometry_is_2d);
		EXPECT_EQ(s.odometry.mean.z(), 0.0);
		EXPECT_EQ(s.odometry.mean.pitch(), 0.0);
		EXPECT_EQ(s.odometry.mean.roll(), 0.0);
		EXPECT_EQ(s.odometry.cov(2, 2), 0.0);
		EXPECT_EQ(s.odometry.cov(4, 4), 0.0);
		EXPECT_EQ(s.odometry.cov(5, 5), 0.0);
		EXPECT_GT(s.odometry.cov(0, 0), 0.0);
		EXPECT_GT(s.odometry.cov(3, 3), 0.0);
		if (s.odometry.mean.norm() > 0.1) moved = true;
	}
	EXPECT_TRUE(moved);
}

TEST(RawlogReader, NoncenteredSensorPose)
{
	const auto log = read_rawlog(kDatasets + "/kf-slam_6D_demo_noncentered.rawlog");
	ASSERT_EQ(log.steps.size(), 599u);
	const auto& p = log.steps[5].sensor_pose;
	EXPECT_NEAR(p.x(), 0.5, 1e-6);
	EXPECT_NEAR(p.y(), 0.2, 1e-6);
	EXPECT_NEAR(p.z(), 0.1, 1e-6);
	EXPECT_NEAR(p.yaw(), mrpt::DEG2RAD(80.0), 1e-6);
	EXPECT_NEAR(p.pitch(), mrpt::DEG2RAD(-20.0), 1e-6);
	EXPECT_NEAR(p.roll(), mrpt::DEG2RAD(10.0), 1e-6);
}

TEST(RawlogReader, UnknownIdsRejectedWithReason)
{
	const std::string msg = expect_error(kDatasets + "/kf-slam_6D_demo_DA.rawlog");
	EXPECT_NE(msg.find("kf-slam_6D_demo_DA.rawlog"), std::string::npos) << msg;
	EXPECT_NE(msg.find("data association"), std::string::npos) << msg;
	RawlogReaderOptions opt;
	opt.require_landmark_ids = false;
	const auto log = read_rawlog(kDatasets + "/kf-slam_6D_demo_DA.rawlog", opt);
	EXPECT_EQ(log.skipped_readings, 0u);
	EXPECT_GT(log.readings, 0u);
}

TEST(RawlogReader, GroundTruthPath)
{
	const auto gt = ground_truth_poses(kDatasets + "/kf-slam_6D_demo_ground_truth_robot_path.txt");
	EXPECT_EQ(gt.size(), 600u);
	const auto d = temp_dir();
	write_bytes((d / "bad.txt").string(), "% comment\n0 0 0 0 0 0\n1 2 3 4 5\n");
	try
	{
		ground_truth_poses((d / "bad.txt").string());
		FAIL() << "no exception";
	}
	catch (const std::runtime_error& e)
	{
		EXPECT_NE(std::string(e.what()).find("bad.txt:3:"), std::string::npos) << e.what();
		EXPECT_NE(std::string(e.what()).find("found 5"), std::string::npos) << e.what();
	}
	EXPECT_THROW(ground_truth_poses((d / "missing.txt").string()), std::runtime_error);
}

TEST(RawlogReader, MissingFile)
{
	const std::string msg = expect_error("/nonexistent/dir/x.rawlog");
	EXPECT_NE(msg.find("/nonexistent/dir/x.rawlog"), std::string::npos) << msg;
	EXPECT_NE(msg.find("does not exist"), std::string::npos) << msg;
}

TEST(RawlogReader, NotARawlog)
{
	const auto d = temp_dir();
	const std::string path = (d / "text.rawlog").string();
	write_bytes(path, "this is a plain text file, not a rawlog\nsecond line\n");
	const std::string msg = expect_error(path);
	EXPECT_NE(msg.find(path), std::string::npos) << msg;
	EXPECT_NE(msg.find("not an MRPT rawlog"), std::string::npos) << msg;
	// An empty file has no steps.
	write_bytes(path, "");
	const std::string msg2 = expect_error(path);
	EXPECT_NE(msg2.find("no action/sensory-frame pairs"), std::string::npos) << msg2;
}

TEST(RawlogReader, TruncatedGzipCopyFailsWithStepCount)
{
	const auto d = temp_dir();
	const std::string bytes = read_bytes(kDatasets + "/kf-slam_6D_demo.rawlog");
	ASSERT_GT(bytes.size(), 1000u);
	for (double frac : {0.3, 0.5, 0.97})
	{
		const std::string path = (d / "cut.rawlog").string();
		write_bytes(path, bytes.substr(0, std::size_t(double(bytes.size()) * frac)));
		const std::string msg = expect_error(path);
		EXPECT_NE(msg.find(path), std::string::npos) << msg;
		EXPECT_NE(msg.find("truncated"), std::string::npos) << msg;
		EXPECT_NE(msg.find("complete steps"), std::string::npos) << msg;
		// Documented policy: allow_truncated keeps the complete steps.
		RawlogReaderOptions opt;
		opt.allow_truncated = true;
		const auto log = read_rawlog(path, opt);
		EXPECT_TRUE(log.truncated);
		EXPECT_GT(log.steps.size(), 0u);
		EXPECT_LT(log.steps.size(), 599u);
		EXPECT_GE(log.warning_count, 1u);
		EXPECT_NE(msg.find(std::to_string(log.steps.size()) + " complete steps"), std::string::npos) << msg;
	}
}

TEST(RawlogReader, TruncatedPlainFileInsideAnObject)
{
	const auto d = temp_dir();
	const std::string path = (d / "plain.rawlog").string();
	write_synth(path, SynthOptions{}, /*gz=*/false);
	const auto full = read_rawlog(path);
	EXPECT_EQ(full.steps.size(), 5u);
	const std::string bytes = read_bytes(path);
	write_bytes(path, bytes.substr(0, bytes.size() - 7));  // inside the trailing action collection
	const std::string msg = expect_error(path);
	EXPECT_NE(msg.find("truncated or corrupt at entry 11 after 5 complete steps"), std::string::npos) << msg;
}

TEST(RawlogReader, NoOdometry)
{
	const auto d = temp_dir();
	const std::string path = (d / "noodo.rawlog").string();
	SynthOptions so;
	so.odometry = false;
	write_synth(path, so);
	const std::string msg = expect_error(path);
	EXPECT_NE(msg.find(path), std::string::npos) << msg;
	EXPECT_NE(msg.find("no odometry"), std::string::npos) << msg;
}

TEST(RawlogReader, NoBearingRangeObservations)
{
	const auto d = temp_dir();
	const std::string path = (d / "noobs.rawlog").string();
	SynthOptions so;
	so.bearing_range = false;
	write_synth(path, so);
	const std::string msg = expect_error(path);
	EXPECT_NE(msg.find(path), std::string::npos) << msg;
	EXPECT_NE(msg.find("no valid bearing-range observation"), std::string::npos) << msg;
}

TEST(RawlogReader, PerReadingCovariancesAreTheReadingsOwnNoise)
{
	const auto d = temp_dir();
	const std::string path = (d / "own.rawlog").string();
	SynthOptions so;
	write_synth(path, so);
	const auto plain = read_rawlog(path);
	EXPECT_EQ(plain.readings_with_own_noise, 0u);
	EXPECT_FALSE(plain.steps[0].readings[0].has_own_noise());

	so.own_covariance = true;
	write_synth(path, so);
	const auto own = read_rawlog(path);
	EXPECT_EQ(own.readings_with_own_noise, 15u);
	const auto& r = own.steps[3].readings[2];
	ASSERT_TRUE(r.has_own_noise());
	EXPECT_NEAR(r.std_range, 0.3, 1e-12);
	EXPECT_NEAR(r.std_yaw, 0.03, 1e-12);
	EXPECT_NEAR(r.std_pitch, 0.06, 1e-12);

	// A correlation is not dropped silently: the reading, its step and the file are named.
	so.correlated = true;
	write_synth(path, so);
	const std::string msg = expect_error(path);
	EXPECT_NE(msg.find(path), std::string::npos) << msg;
	EXPECT_NE(msg.find("step 3"), std::string::npos) << msg;
	EXPECT_NE(msg.find("reading 1"), std::string::npos) << msg;
	EXPECT_NE(msg.find("correlates range, yaw and pitch"), std::string::npos) << msg;

	// A variance that is not finite and > 0 makes the reading invalid: skipped, counted and said.
	so.correlated = false;
	for (double v : {0.0, -1.0, std::numeric_limits<double>::quiet_NaN()})
	{
		so.bad_range_variance = v;
		write_synth(path, so);
		const auto log = read_rawlog(path);
		EXPECT_EQ(log.skipped_readings, 1u);
		EXPECT_EQ(log.readings_with_own_noise, 14u);
		ASSERT_EQ(log.warnings.size(), 1u);
		EXPECT_NE(log.warnings[0].find("variance"), std::string::npos) << log.warnings[0];
	}
}

TEST(RawlogReader, BadReadingsSkippedAndCounted)
{
	const auto d = temp_dir();
	const std::string path = (d / "bad.rawlog").string();
	for (double bad_range : {std::numeric_limits<double>::quiet_NaN(), 0.0, -1.0})
	{
		SynthOptions so;
		so.bad_range = bad_range;
		write_synth(path, so);
		const auto log = read_rawlog(path);
		ASSERT_EQ(log.steps.size(), 5u);
		EXPECT_EQ(log.skipped_readings, 1u);
		EXPECT_EQ(log.readings, 14u);
		EXPECT_EQ(log.warning_count, 1u);
		ASSERT_EQ(log.warnings.size(), 1u);
		EXPECT_NE(log.warnings[0].find("step 1"), std::string::npos) << log.warnings[0];  // SF2 belongs to step 1
		EXPECT_EQ(log.steps[1].skipped_readings, 1u);
		EXPECT_EQ(log.steps[1].readings.size(), 2u);
		// The frame handed to the EKF holds only the valid readings.
		const auto br = log.steps[1].observations->getObservationByClass<mrpt::obs::CObservationBearingRange>();
		ASSERT_TRUE(br);
		EXPECT_EQ(br->sensedData.size(), 2u);
	}
	SynthOptions so;
	so.bad_yaw = std::numeric_limits<double>::infinity();
	write_synth(path, so);
	EXPECT_EQ(read_rawlog(path).skipped_readings, 1u);
	// Unknown IDs: every reading skipped → no valid observation.
	so = SynthOptions{};
	so.id_offset = -10;
	write_synth(path, so);
	EXPECT_NE(expect_error(path).find("data association"), std::string::npos);
}

namespace
{
/** RMS rotation angle (degrees) between the odometry of step k and the true motion
 * GT[k + offset] → GT[k + 1 + offset]. (Rotation tells the pairing apart: the simulated motion has a
 * constant translation but random pitch/roll increments of 2°/4°, measured with 0.1° noise.) */
double odometry_vs_gt_rms(const swba::io::Rawlog& log, const std::vector<mrpt::poses::CPose3D>& gt, int offset)
{
	double sq = 0;
	std::size_t n = 0;
	for (std::size_t k = 0; k < log.steps.size(); k++)
	{
		const long a = long(k) + offset;
		if (a < 0 || std::size_t(a + 1) >= gt.size()) continue;
		const mrpt::poses::CPose3D truth = gt[std::size_t(a) + 1] - gt[std::size_t(a)];
		const auto err = mrpt::poses::Lie::SO<3>::log((log.steps[k].odometry.mean - truth).getRotationMatrix());
		sq += std::pow(mrpt::RAD2DEG(err.norm()), 2);
		n++;
	}
	return std::sqrt(sq / double(n));
}
}  // namespace

TEST(RawlogReader, StepOdometryPairsWithGroundTruthRows)
{
	// Step k's odometry is the motion from GT row k to row k + 1 (noise σ 0.1° per angle).
	const auto log = read_rawlog(kDatasets + "/kf-slam_6D_demo.rawlog");
	const auto gt = ground_truth_poses(kDatasets + "/kf-slam_6D_demo_ground_truth_robot_path.txt");
	ASSERT_EQ(gt.size(), log.steps.size() + 1);
	const double right = odometry_vs_gt_rms(log, gt, 0);
	EXPECT_LT(right, 0.1 * std::sqrt(3.0) * 1.5);
	EXPECT_GT(odometry_vs_gt_rms(log, gt, 1), 5 * right);
	EXPECT_GT(odometry_vs_gt_rms(log, gt, -1), 5 * right);
}

TEST(RawlogReader, SimulLandmarksRawlogs)
{
	// Rawlogs made with MRPT's simul-landmarks from share/rawlogs/*.ini: the committed
	// share/data/rawlogs/reanchor_6D_120 always, and those scripts/make-rawlogs.sh generated (needs
	// mrpt-apps) when present in SWBA_RAWLOG_DIR or <repo>/build/rawlogs.
	const char* env = std::getenv("SWBA_RAWLOG_DIR");
	const std::string generated = env ? env : std::string(SWBA_SHARE_DIR) + "/../build/rawlogs";
	struct Expect
	{
		std::string dir;
		const char* name;
		std::size_t steps;
		double std_range, std_angle_deg;
		bool required;
	};
	int checked = 0;
	for (const Expect& e : {Expect{std::string(SWBA_DATA_DIR) + "/rawlogs", "reanchor_6D_120", 119, 0.01, 0.1, true},
							Expect{generated, "kf-slam_6D_noisy", 599, 0.05, 0.5, false},
							Expect{generated, "large_6D_5000", 4999, 0.01, 0.1, false}})
	{
		const std::string rl = e.dir + "/" + e.name + ".rawlog";
		if (!e.required && !fs::exists(rl)) continue;
		checked++;
		const auto log = read_rawlog(rl);
		EXPECT_EQ(log.steps.size(), e.steps) << rl;
		EXPECT_EQ(log.skipped_readings, 0u);
		EXPECT_EQ(log.steps_with_odometry, e.steps);
		EXPECT_NEAR(log.steps[0].sensor_std_range, e.std_range, 1e-7);
		EXPECT_NEAR(log.steps[0].sensor_std_yaw, mrpt::DEG2RAD(e.std_angle_deg), 1e-7);
		const auto gt = ground_truth_poses(e.dir + "/" + e.name + "_ground_truth_robot_path.txt");
		ASSERT_EQ(gt.size(), e.steps + 1);
		// Step k's odometry rotation is the true motion row k → k+1 up to the simulated 0.1° per angle,
		// and clearly not the motion of a neighbouring row pair.
		const double right = odometry_vs_gt_rms(log, gt, 0);
		EXPECT_LT(right, 0.1 * std::sqrt(3.0) * 1.5) << rl;
		EXPECT_GT(odometry_vs_gt_rms(log, gt, 1), 5 * right) << rl;
	}
	EXPECT_GE(checked, 1);
}

TEST(RawlogReader, PlanarDetection)
{
	auto log = read_rawlog(kDatasets + "/kf-slam_demo.rawlog");
	EXPECT_TRUE(swba::io::is_planar(log.steps));
	EXPECT_FALSE(swba::io::is_planar(read_rawlog(kDatasets + "/kf-slam_6D_demo.rawlog").steps));
	// One reading with a pitch makes the step, and so the rawlog, not planar.
	auto& step = log.steps.at(10);
	ASSERT_FALSE(step.readings.empty());
	step.readings.front().pitch = 0.01;
	EXPECT_FALSE(swba::io::is_planar_step(step));
	EXPECT_FALSE(swba::io::is_planar(log.steps));
	step.readings.front().pitch = 0.0;
	// A 3D odometry is not planar either.
	step.odometry_is_2d = false;
	EXPECT_FALSE(swba::io::is_planar(log.steps));
}
