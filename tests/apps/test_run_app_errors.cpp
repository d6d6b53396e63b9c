// swba run on bad input (through run_app, what the command calls): one-line errors naming the file,
// and single bad readings counted, never a crash.
#include <swba/apps/run.h>

#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CActionRobotMovement3D.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/serialization/CArchive.h>

#include <gtest/gtest.h>

#include "test_temp_dir.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>

namespace
{
namespace fs = std::filesystem;
using swba::apps::RunOptions;


/** A small rawlog SF0, AC0, SF1, ...: the robot moves 0.3 m forward per step (noise-free) and sees 4
 * fixed landmarks ahead of it; `nan_reading_step` ≥ 0 gives one reading of that frame a NaN range. */
struct Synth
{
	int steps = 8;
	bool odometry = true;
	bool bearing_range = true;
	int nan_reading_step = -1;
	bool own_covariance = false;  ///< validCovariances, every reading σ 0.02 m / 0.004 rad
};

void write_synth(const std::string& path, const Synth& so)
{
	mrpt::io::CFileGZOutputStream out(path);
	auto arch = mrpt::serialization::archiveFrom(out);
	const double landmarks[4][3] = {{4, 1, 0.5}, {5, -1, -0.3}, {6, 0.5, 1}, {7, -0.5, 0}};
	for (int i = 0; i <= so.steps; i++)
	{
		const mrpt::poses::CPose3D robot(0.3 * i, 0, 0, 0, 0, 0);
		mrpt::obs::CSensoryFrame sf;
		if (so.bearing_range)
		{
			auto obs = mrpt::obs::CObservationBearingRange::Create();
			obs->sensor_std_range = 0.01f;
			obs->sensor_std_yaw = 0.002f;
			obs->sensor_std_pitch = 0.002f;
			obs->validCovariances = so.own_covariance;
			for (int j = 0; j < 4; j++)
			{
				const auto l = robot.inverseComposePoint(
					mrpt::math::TPoint3D(landmarks[j][0], landmarks[j][1], landmarks[j][2]));
				mrpt::obs::CObservationBearingRange::TMeasurement m;
				m.landmarkID = j;
				m.range = static_cast<float>(l.norm());
				m.yaw = static_cast<float>(std::atan2(l.y, l.x));
				m.pitch = static_cast<float>(-std::asin(l.z / l.norm()));
				if (i == so.nan_reading_step && j == 2) m.range = std::numeric_limits<float>::quiet_NaN();
				m.covariance.setZero();
				m.covariance(0, 0) = 4e-4;
				m.covariance(1, 1) = m.covariance(2, 2) = 1.6e-5;
				obs->sensedData.push_back(m);
			}
			sf.insert(obs);
		}
		arch << sf;
		mrpt::obs::CActionCollection acts;
		if (so.odometry)
		{
			mrpt::obs::CActionRobotMovement3D act;
			act.poseChange.mean = mrpt::poses::CPose3D(0.3, 0, 0, 0, 0, 0);
			act.poseChange.cov.setIdentity();
			act.poseChange.cov *= 1e-4;
			acts.insert(act);
		}
		arch << acts;
	}
}

std::string run_error(const RunOptions& o)
{
	std::ostringstream out, log;
	try
	{
		swba::apps::run_app(o, out, log);
	}
	catch (const std::exception& e)
	{
		return e.what();
	}
	ADD_FAILURE() << "no error for rawlog " << o.rawlog;
	return {};
}

RunOptions quick_options(const fs::path& dir, const std::string& rawlog)
{
	RunOptions o;
	o.rawlog = rawlog;
	o.out_dir = (dir / "out").string();
	o.windows = {3};
	o.plots = false;
	o.progress = false;
	return o;
}
}  // namespace

TEST(RunAppErrors, MissingRawlogNamesTheFile)
{
	const auto d = temp_dir();
	const std::string msg = run_error(quick_options(d, (d / "none.rawlog").string()));
	EXPECT_NE(msg.find((d / "none.rawlog").string()), std::string::npos) << msg;
	EXPECT_NE(msg.find("does not exist"), std::string::npos) << msg;
	EXPECT_FALSE(fs::exists(d / "out")) << "nothing is written on bad input";
}

TEST(RunAppErrors, TruncatedRawlog)
{
	const auto d = temp_dir();
	std::ifstream in(std::string(SWBA_MRPT_DATASETS) + "/kf-slam_6D_demo.rawlog", std::ios::binary);
	const std::string bytes((std::istreambuf_iterator<char>(in)), {});
	ASSERT_GT(bytes.size(), 1000u);
	const std::string path = (d / "cut.rawlog").string();
	{
		std::ofstream out(path, std::ios::binary);
		out.write(bytes.data(), std::streamsize(bytes.size() / 2));
	}
	const std::string msg = run_error(quick_options(d, path));
	EXPECT_NE(msg.find(path), std::string::npos) << msg;
	EXPECT_NE(msg.find("truncated"), std::string::npos) << msg;
	EXPECT_EQ(msg.find('\n'), std::string::npos) << "one line: " << msg;
}

TEST(RunAppErrors, RawlogWithoutOdometry)
{
	const auto d = temp_dir();
	const std::string path = (d / "noodo.rawlog").string();
	Synth so;
	so.odometry = false;
	write_synth(path, so);
	const std::string msg = run_error(quick_options(d, path));
	EXPECT_NE(msg.find(path), std::string::npos) << msg;
	EXPECT_NE(msg.find("no odometry"), std::string::npos) << msg;
}

TEST(RunAppErrors, RawlogWithoutBearingRange)
{
	const auto d = temp_dir();
	const std::string path = (d / "noobs.rawlog").string();
	Synth so;
	so.bearing_range = false;
	write_synth(path, so);
	const std::string msg = run_error(quick_options(d, path));
	EXPECT_NE(msg.find(path), std::string::npos) << msg;
	EXPECT_NE(msg.find("no valid bearing-range observation"), std::string::npos) << msg;
}

TEST(RunAppErrors, WindowBelowTwoRejectedBeforeReading)
{
	const auto d = temp_dir();
	RunOptions o = quick_options(d, (d / "none.rawlog").string());
	o.windows = {5, 1};
	const std::string msg = run_error(o);
	EXPECT_NE(msg.find("window size must be >= 2, got 1"), std::string::npos) << msg;
}

TEST(RunAppErrors, NanReadingIsCountedAndTheRunCompletes)
{
	const auto d = temp_dir();
	const std::string path = (d / "nan.rawlog").string();
	Synth so;
	so.nan_reading_step = 4;
	write_synth(path, so);
	RunOptions o = quick_options(d, path);  // no ground truth next to it: no APE, still a table
	std::ostringstream out, log;
	const auto report = swba::apps::run_app(o, out, log);
	EXPECT_EQ(report.steps, 8u);
	EXPECT_EQ(report.skipped_readings, 1u);
	EXPECT_NE(log.str().find("warning: "), std::string::npos) << log.str();
	EXPECT_NE(log.str().find("no ground truth"), std::string::npos) << log.str();
	ASSERT_EQ(report.rows.size(), 2u + 2u + 2u);  // 2 EKF, window online + lagged, batch from two starts
	for (const auto& r : report.rows)
	{
		EXPECT_FALSE(r.failed) << r.label << ": " << r.failure;
		EXPECT_FALSE(r.has_ape);
		EXPECT_EQ(r.estimate.size(), 8u) << r.label;
	}
	EXPECT_NE(out.str().find("no ground truth: APE not computed"), std::string::npos) << out.str();
	EXPECT_TRUE(fs::exists(d / "out" / "summary.json"));
	{
		std::ifstream f(d / "out" / "summary.json");
		const std::string json((std::istreambuf_iterator<char>(f)), {});
		EXPECT_NE(json.find("\"readings\": 31,\n  \"skipped_readings\": 1,\n  \"readings_with_own_noise\": 0"),
				  std::string::npos)
			<< json.substr(0, 300);
	}
	EXPECT_FALSE(fs::exists(d / "out" / "gt.tum"));
	// The estimates follow the true motion: 0.3 m per step along x.
	const auto& batch = report.rows[report.rows.size() - 2];  // then batch_alt, the other start
	ASSERT_EQ(batch.name, "batch");
	EXPECT_NEAR(batch.estimate.poses.back().x(), 0.3 * 8, 1e-3);
}

TEST(RunAppErrors, PerReadingCovariancesAreCountedAndTheEkfRowSaysItDoesNotUseThem)
{
	const auto d = temp_dir();
	const std::string path = (d / "own.rawlog").string();
	Synth so;
	so.own_covariance = true;
	write_synth(path, so);
	std::ostringstream out, log;
	const auto report = swba::apps::run_app(quick_options(d, path), out, log);
	EXPECT_NE(log.str().find("32 readings, 32 with their own covariance (validCovariances"), std::string::npos)
		<< log.str();
	bool ekf_note = false;
	for (const auto& n : report.notes)
		ekf_note |= n.find("32 readings carry their own covariance") != std::string::npos;
	EXPECT_TRUE(ekf_note);
	for (const auto& r : report.rows) EXPECT_FALSE(r.failed) << r.label << ": " << r.failure;
}

namespace
{
/** A ground truth for write_synth's motion (0.3 m per step along x), `rows` rows. */
void write_synth_ground_truth(const std::string& path, int rows)
{
	std::ofstream f(path);
	for (int i = 0; i < rows; i++) f << 0.3 * i << " 0 0 0 0 0\n";
}
}  // namespace

TEST(RunAppErrors, GroundTruthLongerThanTheRawlogIsWarnedAbout)
{
	// A plain rawlog cut at an object boundary reads as a complete shorter run; only the ground truth
	// (here 20 rows for 8 steps) shows it.
	const auto d = temp_dir();
	const std::string path = (d / "short.rawlog").string();
	write_synth(path, Synth{});
	RunOptions o = quick_options(d, path);
	o.ground_truth = (d / "gt.txt").string();
	for (const int rows : {9, 10, 20})
	{
		write_synth_ground_truth(o.ground_truth, rows);
		std::ostringstream out, log;
		swba::apps::run_app(o, out, log);
		const bool warned = log.str().find("warning: the ground truth has " + std::to_string(rows) +
										   " rows but the rawlog only 8 steps") != std::string::npos;
		EXPECT_EQ(warned, rows > 9) << rows << " rows:\n" << log.str();
	}
}

TEST(RunAppErrors, InputsThatAreNotRegularFilesAreRefusedInOneLine)
{
	const auto d = temp_dir();
	const std::string rawlog = (d / "ok.rawlog").string();
	write_synth(rawlog, Synth{});
	RunOptions o = quick_options(d, "/dev/zero");  // read forever before
	std::string msg = run_error(o);
	EXPECT_EQ(msg, "rawlog '/dev/zero': is not a regular file (a FIFO, device or socket)");
	o = quick_options(d, d.string());
	msg = run_error(o);
	EXPECT_EQ(msg, "rawlog '" + d.string() + "': is a directory, not a file");
	o = quick_options(d, rawlog);
	o.ground_truth = "/dev/zero";
	msg = run_error(o);
	EXPECT_NE(msg.find("/dev/zero: is not a regular file"), std::string::npos) << msg;
}

TEST(RunAppErrors, ConfigWithoutAnySectionIsAnError)
{
	const auto d = temp_dir();
	RunOptions o;
	const std::string empty = (d / "empty.ini").string(), loose = (d / "loose.ini").string();
	std::ofstream(empty) << "; only a comment\n";
	std::ofstream(loose) << "windows = 5\n[run]\n";
	try
	{
		swba::apps::load_run_config(empty, o);
		ADD_FAILURE() << "an empty config was accepted";
	}
	catch (const std::exception& e)
	{
		EXPECT_NE(std::string(e.what()).find("no section (expected some of [run]"), std::string::npos) << e.what();
	}
	try
	{
		swba::apps::load_run_config(loose, o);
		ADD_FAILURE() << "a key before any section was accepted";
	}
	catch (const std::exception& e)
	{
		EXPECT_NE(std::string(e.what()).find("key 'windows' before any [section]"), std::string::npos) << e.what();
	}
}

TEST(RunAppErrors, MessagesNeverCarryRawFileBytes)
{
	// MRPT quotes the "class name" it read from a file that is no rawlog: control and high bytes must be
	// escaped (\xNN), never copied to the terminal.
	const auto d = temp_dir();
	const std::string path = (d / "bytes.rawlog").string();
	{
		std::ofstream f(path, std::ios::binary);
		// 0x85: an object whose class name has 5 bytes (MRPT's format), then ESC [ 2 0xff BEL.
		const unsigned char b[] = {0x85, 0x1b, '[', '2', 0xff, 0x07, 0x00, 0x00, 0x00, 0x00};
		for (int i = 0; i < 20; i++) f.write(reinterpret_cast<const char*>(b), sizeof(b));
	}
	const std::string msg = run_error(quick_options(d, path));
	EXPECT_NE(msg.find("class '\\x1b[2\\xff\\x07'"), std::string::npos) << msg;
	for (const unsigned char c : msg) EXPECT_TRUE(c >= 0x20 && c < 0x7f) << "byte " << int(c) << " in: " << msg;
}

TEST(RunAppErrors, StopRequestKeepsTheCompleteRowsAndMarksTheRest)
{
	// The stop request arrives while the first window (W = 3) runs: the EKF rows are complete and on
	// disk, the window's rows are interrupted after the steps done, the next window and the batch never
	// start; summary.json says which.
	const auto d = temp_dir();
	const std::string path = (d / "run.rawlog").string();
	write_synth(path, Synth{});
	RunOptions o = quick_options(d, path);
	o.windows = {3, 4};
	int polls = 0;
	bool in_window = false;
	std::ostringstream out, log;
	const auto report = swba::apps::run_app(o, out, log, [&] {
		// The EKF polls once per step (8 + 8), then the first window per step: stop at its 5th step.
		return in_window = ++polls > 16 + 4;
	});
	ASSERT_TRUE(in_window);
	EXPECT_TRUE(swba::apps::run_interrupted(report));
	ASSERT_EQ(report.rows.size(), 2u + 4u + 1u);
	for (std::size_t i = 0; i < 2; i++) EXPECT_FALSE(report.rows[i].failed) << report.rows[i].label;
	for (std::size_t i = 2; i < 4; i++)
	{
		EXPECT_TRUE(report.rows[i].interrupted) << report.rows[i].label;
		EXPECT_EQ(report.rows[i].failed_step, 4u) << report.rows[i].label;
	}
	for (std::size_t i = 4; i < 7; i++)
	{
		EXPECT_TRUE(report.rows[i].interrupted) << report.rows[i].label;
		EXPECT_EQ(report.rows[i].failed_step, 0u) << report.rows[i].label;
	}
	EXPECT_NE(out.str().find("INTERRUPTED after 4 steps"), std::string::npos) << out.str();
	std::ifstream js(d / "out" / "summary.json");
	const std::string json((std::istreambuf_iterator<char>(js)), {});
	std::size_t interrupted = 0;
	for (std::size_t at = json.find("\"interrupted\": true"); at != std::string::npos;
		 at = json.find("\"interrupted\": true", at + 1))
		interrupted++;
	EXPECT_EQ(interrupted, 5u) << json;
}
