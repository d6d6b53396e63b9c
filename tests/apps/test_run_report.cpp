// swba run reports: APE pairing with the ground truth, summary.json shape, table, CSV, GT checks.
#include <swba/apps/run.h>
#include <swba/eval/ground_truth.h>

#include <gtest/gtest.h>

#include "test_temp_dir.h"
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

namespace
{
namespace fs = std::filesystem;
using mrpt::poses::CPose3D;
using swba::apps::RunReport;
using swba::apps::RunRow;


std::vector<CPose3D> random_path(std::size_t n, unsigned seed)
{
	std::mt19937 rng(seed);
	std::normal_distribution<double> step(0.0, 0.3), turn(0.0, 0.1);
	std::vector<CPose3D> rows;
	CPose3D p;
	for (std::size_t i = 0; i < n; i++)
	{
		rows.push_back(p);
		p = p + CPose3D(0.5 + step(rng), step(rng), step(rng), turn(rng), turn(rng), turn(rng));
	}
	return rows;
}

using Json = nlohmann::ordered_json;

/** The keys of a JSON object, in the file's order. */
std::vector<std::string> keys_of(const Json& j)
{
	std::vector<std::string> keys;
	for (const auto& item : j.items()) keys.push_back(item.key());
	return keys;
}

/** A report with one row of each kind (EKF failed, window online/lagged, batch). */
RunReport sample_report()
{
	const auto gt = random_path(12, 3);
	RunReport rep;
	rep.rawlog = "/data/demo \"quoted\".rawlog";
	rep.ground_truth = "/data/demo_ground_truth_robot_path.txt";
	rep.steps = 11;
	auto make = [&](const std::string& name, const std::string& label, int W, const std::string& traj, double noise) {
		RunRow r;
		r.name = name;
		r.label = label;
		r.window = W;
		r.trajectory = traj;
		for (std::size_t k = 0; k < 11; k++)
			r.estimate.push_back(double(k + 1), gt[k + 1] + CPose3D(noise * double(k % 3), 0, 0, 0, 0, 0));
		const auto [t, f] = swba::eval::ape_against_ground_truth(gt, r.estimate);
		r.ape_trans = t;
		r.ape_full = f;
		r.has_ape = true;
		r.seconds = 0.011;
		r.ms_per_step = 1.0;
		r.steps = 11;
		return r;
	};
	RunRow ekf = make("ekf", "ekf kfEKFNaive", 0, "online", 0.0);
	ekf.method = "kfEKFNaive";
	ekf.failed = true;
	ekf.failed_step = 7;
	ekf.failure = "Vehicle pose quaternion norm is not >0";
	ekf.has_ape = false;
	ekf.estimate.poses.resize(7);
	ekf.estimate.stamps.resize(7);
	rep.rows.push_back(ekf);
	RunRow on = make("window", "window W=10", 10, "online", 0.02);
	on.policy = "slam";
	on.fej = true;
	rep.rows.push_back(on);
	RunRow lag = make("window", "window W=10 lagged", 10, "lagged", 0.01);
	lag.policy = "slam";
	lag.fej = true;
	rep.rows.push_back(lag);
	rep.rows.push_back(make("batch", "batch", 0, "smoothed", 0.005));
	return rep;
}
}  // namespace

TEST(RunApe, EstimateAfterStepKPairsWithGroundTruthRowKPlus1)
{
	const auto gt = random_path(50, 1);
	// The perfect estimate: after step k (t = k + 1) the pose is GT row k + 1.
	swba::eval::Trajectory right, shifted;
	for (std::size_t k = 0; k + 1 < gt.size(); k++)
	{
		right.push_back(double(k + 1), gt[k + 1]);
		shifted.push_back(double(k + 1), gt[k]);  // the off-by-one mistake
	}
	const auto [t_right, f_right] = swba::eval::ape_against_ground_truth(gt, right);
	EXPECT_EQ(t_right.count, 49u);
	EXPECT_LT(t_right.rmse, 1e-12);
	EXPECT_LT(f_right.rmse, 1e-12);
	const auto [t_shift, f_shift] = swba::eval::ape_against_ground_truth(gt, shifted);
	// Each error is the distance between consecutive GT positions (≥ ~0.3 m here).
	double sse = 0;
	for (std::size_t k = 0; k + 1 < gt.size(); k++)
	{
		const double d = (gt[k + 1].translation() - gt[k].translation()).norm();
		sse += d * d;
	}
	EXPECT_NEAR(t_shift.sse, sse, 1e-9 * sse);
	EXPECT_GT(f_shift.rmse, 0.1);

	// A known offset of the estimate after step 9 only: the 10th error is exactly that offset.
	auto offset = right;
	offset.poses[9] = offset.poses[9] + CPose3D(0, 0.25, 0, 0, 0, 0);
	const auto [t_off, f_off] = swba::eval::ape_against_ground_truth(gt, offset);
	EXPECT_NEAR(t_off.max, 0.25, 1e-12);
	EXPECT_NEAR(t_off.sse, 0.0625, 1e-12);
	EXPECT_NEAR(f_off.max, 0.25, 1e-12);  // ‖E − I‖_F of a pure translation
}

TEST(RunApe, PairingChecksStampsAndRows)
{
	const auto gt = random_path(5, 2);
	swba::eval::Trajectory est;
	est.push_back(4.0, gt[4]);
	EXPECT_EQ(swba::eval::paired_ground_truth(gt, est).poses[0].translation(), gt[4].translation());
	est.push_back(5.0, gt[4]);	// row 5 does not exist
	EXPECT_THROW(swba::eval::paired_ground_truth(gt, est), std::runtime_error);
	swba::eval::Trajectory frac;
	frac.push_back(1.5, gt[1]);
	EXPECT_THROW(swba::eval::paired_ground_truth(gt, frac), std::runtime_error);
	swba::eval::Trajectory zero;
	zero.push_back(0.0, gt[0]);	 // t = 0 is the start, not the estimate after a step
	EXPECT_THROW(swba::eval::paired_ground_truth(gt, zero), std::runtime_error);
}

TEST(RunApe, DefaultGroundTruthPathFollowsMrptNaming)
{
	EXPECT_EQ(swba::eval::default_ground_truth_path("/a/b/kf-slam_6D_demo.rawlog"),
			  "/a/b/kf-slam_6D_demo_ground_truth_robot_path.txt");
	EXPECT_EQ(swba::eval::default_ground_truth_path("x.rawlog.gz"), "x_ground_truth_robot_path.txt");
}

namespace
{
/** `path` with the contents `text`. */
void write_text(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

/** read_ground_truth_for(path, steps) throws std::runtime_error naming `path` and saying `reason`. */
void expect_ground_truth_error(const std::string& path, std::size_t steps, const std::string& reason)
{
	try
	{
		swba::eval::read_ground_truth_for(path, steps);
		FAIL() << "no error";
	}
	catch (const std::runtime_error& e)
	{
		const std::string msg = e.what();
		EXPECT_NE(msg.find(path), std::string::npos) << msg;
		EXPECT_NE(msg.find(reason), std::string::npos) << msg;
	}
}
}  // namespace

TEST(RunGroundTruth, TooShortOrWrongColumnsAreErrorsNamingTheFile)
{
	const auto d = temp_dir();
	const std::string short_gt = (d / "short_gt.txt").string();
	std::string rows = "% x y z yaw pitch roll\n";
	for (int i = 0; i < 10; i++) rows += std::to_string(i) + " 0 0 0 0 0\n";
	write_text(short_gt, rows);
	EXPECT_EQ(swba::eval::read_ground_truth_for(short_gt, 9).size(), 10u);  // exactly steps + 1 rows
	expect_ground_truth_error(short_gt, 10, "10 rows, but the rawlog has 10 steps and needs 11 rows");
	const std::string five = (d / "five_columns.txt").string();
	write_text(five, "0 0 0 0 0 0\n1 0 0 0 0\n");
	expect_ground_truth_error(five, 1, "6");
}

TEST(RunSummaryJson, ShapeOfTheDocumentedExample)
{
	const RunReport rep = sample_report();
	const Json j = Json::parse(swba::apps::format_summary_json(rep));
	ASSERT_TRUE(j.is_object());
	EXPECT_EQ(keys_of(j), (std::vector<std::string>{"rawlog", "ground_truth", "steps", "landmarks", "readings", "skipped_readings",
											   "readings_with_own_noise", "estimators"}));
	EXPECT_EQ(j["rawlog"], rep.rawlog);	 // quotes in the path survive the escaping
	EXPECT_EQ(j["ground_truth"], rep.ground_truth);
	EXPECT_EQ(j["steps"], 11);
	ASSERT_TRUE(j["estimators"].is_array());
	ASSERT_EQ(j["estimators"].size(), 4u);
	const std::vector<std::string> stats = {"rmse", "mean", "median", "max", "min", "sse", "std"};
	const std::vector<std::string> row_keys = {"name", "label", "window", "trajectory", "policy", "fej", "method", "file",
											   "poses", "ape_trans", "ape_full", "ape_rot", "rpe_trans", "association", "seconds", "ms_per_step",
											   "covariance_seconds", "steps_processed", "readings", "start", "final_cost", "diverged", "divergence",
											   "reading_misfit", "nees", "failed", "failed_step", "failure", "interrupted"};
	for (std::size_t i = 0; i < rep.rows.size(); i++)
	{
		const Json& e = j["estimators"][i];
		const RunRow& r = rep.rows[i];
		EXPECT_EQ(keys_of(e), row_keys) << r.label;
		EXPECT_EQ(e["name"], r.name);
		EXPECT_EQ(e["trajectory"], r.trajectory);
		if (r.name == "window")
		{
			EXPECT_EQ(e["window"], 10);
			EXPECT_EQ(e["policy"], "slam");
			EXPECT_EQ(e["fej"], true);
		}
		else
		{
			EXPECT_TRUE(e["window"].is_null()) << r.label;
			EXPECT_TRUE(e["fej"].is_null()) << r.label;
		}
		EXPECT_EQ(e["failed"], r.failed);
		if (r.has_ape)
		{
			for (const char* part : {"ape_trans", "ape_full"})
			{
				ASSERT_TRUE(e[part].is_object());
				EXPECT_EQ(keys_of(e[part]), stats) << part;
			}
			EXPECT_EQ(e["ape_trans"]["rmse"].get<double>(), r.ape_trans.rmse);	// round trip: the same double
			EXPECT_EQ(e["ape_full"]["max"].get<double>(), r.ape_full.max);
			EXPECT_TRUE(e["failure"].is_null());
			EXPECT_TRUE(e["failed_step"].is_null());
		}
		else
		{
			EXPECT_TRUE(e["ape_trans"].is_null());
			EXPECT_EQ(e["failure"], "Vehicle pose quaternion norm is not >0");
			EXPECT_EQ(e["failed_step"], 7);
			EXPECT_EQ(e["method"], "kfEKFNaive");
		}
		EXPECT_EQ(e["poses"], r.estimate.size());
		EXPECT_EQ(e["ms_per_step"].get<double>(), r.ms_per_step);
	}
}

TEST(RunSummaryJson, NoGroundTruthAndNonFiniteTimesAreNull)
{
	RunReport rep = sample_report();
	rep.ground_truth.clear();
	rep.rows[1].seconds = std::nan("");
	rep.rows[1].ms_per_step = HUGE_VAL;
	const Json j = Json::parse(swba::apps::format_summary_json(rep));
	EXPECT_TRUE(j["ground_truth"].is_null());
	EXPECT_TRUE(j["estimators"][1]["seconds"].is_null());
	EXPECT_TRUE(j["estimators"][1]["ms_per_step"].is_null());
	EXPECT_EQ(j["estimators"][2]["seconds"].get<double>(), 0.011);
}

TEST(RunSummaryJson, BytesThatAreNotUtf8StillGiveValidJson)
{
	RunReport rep = sample_report();
	rep.rawlog = "/data/caf\xe9.rawlog";	 // Latin-1 é
	rep.rows[0].failure = "bad byte \xff";
	const Json j = Json::parse(swba::apps::format_summary_json(rep));
	EXPECT_EQ(j["rawlog"], "/data/caf\xef\xbf\xbd.rawlog");  // U+FFFD in its place
	EXPECT_EQ(j["estimators"][0]["failure"], "bad byte \xef\xbf\xbd");
}

TEST(RunTable, OneRowPerEstimatorWithFailures)
{
	const RunReport rep = sample_report();
	const std::string table = swba::apps::format_comparison_table(rep);
	std::vector<std::string> lines;
	std::string line;
	std::istringstream in(table);
	while (std::getline(in, line)) lines.push_back(line);
	ASSERT_EQ(lines.size(), 4u + rep.rows.size()) << table;  // title, pairing note, header, rule, rows
	EXPECT_NE(lines[2].find("trans rmse"), std::string::npos);
	EXPECT_NE(lines[2].find("full rmse"), std::string::npos);
	EXPECT_NE(lines[2].find("ms/step"), std::string::npos);
	EXPECT_EQ(lines[4].rfind("ekf kfEKFNaive", 0), 0u);
	EXPECT_NE(lines[4].find("FAILED at step 7: Vehicle pose quaternion norm is not >0"), std::string::npos) << lines[4];
	char rmse[32];
	std::snprintf(rmse, sizeof(rmse), "%.6f", rep.rows[1].ape_trans.rmse);
	EXPECT_NE(lines[5].find(rmse), std::string::npos) << lines[5];
	EXPECT_NE(lines[6].find("lagged"), std::string::npos);
	EXPECT_EQ(lines[7].rfind("batch", 0), 0u);
}

TEST(RunTable, ColumnsStayAlignedWithALargeWindow)
{
	RunReport rep = sample_report();
	rep.rows[1].window = rep.rows[2].window = 1000000;
	const std::string table = swba::apps::format_comparison_table(rep);
	std::vector<std::string> lines;
	std::string line;
	std::istringstream in(table);
	while (std::getline(in, line)) lines.push_back(line);
	ASSERT_GE(lines.size(), 8u) << table;
	// The W values end where the header's "W" does, and every trajectory starts under "trajectory".
	const std::size_t w_end = lines[2].find(" W ") + 2, traj = lines[2].find("trajectory");
	for (std::size_t i = 4; i < lines.size(); i++)
	{
		EXPECT_EQ(lines[i][w_end - 1], i == 4 || i == 7 ? '-' : '0') << table;
		EXPECT_EQ(lines[i][w_end], ' ') << table;
		EXPECT_NE(lines[i][traj], ' ') << table;
		EXPECT_EQ(lines[i][traj - 1], ' ') << table;
	}
	EXPECT_EQ(lines[3].size(), lines[2].size());
}

TEST(RunApeText, EvoBlocksPerEstimator)
{
	const RunReport rep = sample_report();
	const std::string text = swba::apps::format_ape_text(rep);
	std::size_t trans = 0, full = 0;
	for (std::size_t p = 0; (p = text.find("APE w.r.t. translation part (m)\n(not aligned)\n\n       max\t", p)) !=
							std::string::npos;
		 p++)
		trans++;
	for (std::size_t p = 0;
		 (p = text.find("APE w.r.t. full transformation (unit-less)\n(not aligned)\n\n", p)) != std::string::npos; p++)
		full++;
	EXPECT_EQ(trans, 3u);  // the failed EKF has none
	EXPECT_EQ(full, 3u);
	EXPECT_NE(text.find("=== ekf kfEKFNaive (online)"), std::string::npos);
	EXPECT_NE(text.find("FAILED at step 7"), std::string::npos);
}

TEST(RunApeCsv, HeaderAndRows)
{
	const RunReport rep = sample_report();
	const std::string csv = swba::apps::format_ape_csv(rep);
	std::istringstream in(csv);
	std::string header;
	std::getline(in, header);
	EXPECT_EQ(header.rfind("label,name,window,trajectory,policy,fej,method,failed,failed_step,poses,trans_rmse,", 0), 0u)
		<< header;
	std::size_t columns = std::count(header.begin(), header.end(), ',') + 1;
	EXPECT_EQ(columns, 10u + 4 * 7u + 8u + 2u + 2u);  // 4 statistics blocks, the association, the times, divergence
	std::string row;
	std::size_t n = 0;
	while (std::getline(in, row))
	{
		EXPECT_EQ(std::size_t(std::count(row.begin(), row.end(), ',')) + 1, columns) << row;
		n++;
	}
	EXPECT_EQ(n, rep.rows.size());
}

TEST(RunSummaryJson, ReadingCountsPerEstimator)
{
	RunReport rep = sample_report();
	swba::estimators::ReadingCounts c;
	c.readings = 100;
	c.gated = 7;
	c.readmitted = 2;
	c.reassociated = 4;
	c.ambiguous = 5;
	c.rematched = 8;
	c.unconfirmed = 1;
	c.excluded = 6;
	c.down_weighted = 3;
	c.young_held_steps = 9;
	c.association_cut = 2;
	rep.rows[1].reading_counts = c;
	const Json j = Json::parse(swba::apps::format_summary_json(rep));
	const Json& with = j["estimators"][1];
	ASSERT_TRUE(with["readings"].is_object());
	EXPECT_EQ(keys_of(with["readings"]),
			  (std::vector<std::string>{"processed", "gated", "readmitted", "reassociated", "ambiguous", "rematched",
										"unconfirmed", "excluded", "down_weighted", "young_held_steps",
										"association_cut"}));
	EXPECT_EQ(with["readings"]["processed"], 100);
	EXPECT_EQ(with["readings"]["gated"], 7);
	EXPECT_EQ(with["readings"]["readmitted"], 2);
	EXPECT_EQ(with["readings"]["reassociated"], 4);
	EXPECT_EQ(with["readings"]["ambiguous"], 5);
	EXPECT_EQ(with["readings"]["rematched"], 8);
	EXPECT_EQ(with["readings"]["unconfirmed"], 1);
	EXPECT_EQ(with["readings"]["excluded"], 6);
	EXPECT_EQ(with["readings"]["down_weighted"], 3);
	EXPECT_EQ(with["readings"]["young_held_steps"], 9);
	EXPECT_EQ(with["readings"]["association_cut"], 2);
	EXPECT_TRUE(j["estimators"][0]["readings"].is_null());
}

TEST(RunSummaryJson, AssociationQualityRotationApeAndRpeAreWritten)
{
	RunReport rep = sample_report();
	RunRow& w = rep.rows[1];
	swba::estimators::AssociationQuality q;
	q.readings = 200;
	q.associated = 190;
	q.correct = 171;
	q.landmarks = 21;
	q.true_landmarks = 20;
	q.duplicates = 1;
	q.spurious = 2;
	w.association = q;
	w.ape_rot.rmse = 0.25;
	w.has_rpe = true;
	w.rpe_trans.rmse = 0.03;
	const Json j = Json::parse(swba::apps::format_summary_json(rep));
	const Json& e = j["estimators"][1];
	EXPECT_DOUBLE_EQ(e["association"]["correct_percent"].get<double>(), 90.0);
	EXPECT_EQ(e["association"]["duplicates"], 1);
	EXPECT_EQ(e["association"]["spurious"], 2);
	EXPECT_DOUBLE_EQ(e["ape_rot"]["rmse"].get<double>(), 0.25);
	EXPECT_DOUBLE_EQ(e["rpe_trans"]["rmse"].get<double>(), 0.03);
	EXPECT_TRUE(j["estimators"][0]["association"].is_null());  // the failed EKF: none
	// ape.csv: the same figures in the named columns.
	std::istringstream csv(swba::apps::format_ape_csv(rep));
	std::string header, line;
	std::getline(csv, header);
	std::getline(csv, line);
	std::getline(csv, line);  // the window row
	auto column = [](const std::string& text, const std::string& name_or_empty, std::size_t index) {
		std::vector<std::string> cells;
		std::stringstream ss(text);
		for (std::string c; std::getline(ss, c, ',');) cells.push_back(c);
		if (name_or_empty.empty()) return cells.at(index);
		return std::to_string(std::find(cells.begin(), cells.end(), name_or_empty) - cells.begin());
	};
	for (const auto& [name, value] : std::vector<std::pair<std::string, std::string>>{
			 {"association_correct_percent", "90"}, {"association_duplicates", "1"}, {"association_spurious", "2"},
			 {"rot_rmse", "0.25"}, {"rpe_rmse", "0.03"}})
		EXPECT_EQ(column(line, "", std::stoul(column(header, name, 0))), value) << name << "\n" << header << "\n" << line;
	// The table shows the rotation APE and the RPE.
	const std::string table = swba::apps::format_comparison_table(rep);
	EXPECT_NE(table.find("rot rmse   rpe rmse"), std::string::npos) << table;
	EXPECT_NE(table.find("0.250000   0.030000"), std::string::npos) << table;
}
