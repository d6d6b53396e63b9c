// swba run reports: APE pairing with the ground truth, summary.json shape, table, CSV, GT checks.
#include <swba/apps/run.h>
#include <swba/eval/ground_truth.h>

#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <random>

namespace
{
namespace fs = std::filesystem;
using mrpt::poses::CPose3D;
using swba::apps::RunReport;
using swba::apps::RunRow;

fs::path temp_dir()
{
	const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
	fs::path d = fs::temp_directory_path() / (std::string("swba_runapp_") + info->test_suite_name() + "_" + info->name());
	fs::remove_all(d);
	fs::create_directories(d);
	return d;
}

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

// --- A minimal JSON reader, enough to check the shape of summary.json. ---
struct Json
{
	enum Type
	{
		Null,
		Bool,
		Number,
		String,
		Array,
		Object
	} type = Null;
	bool b = false;
	double num = 0;
	std::string str;
	std::vector<Json> arr;
	std::map<std::string, Json> obj;
	std::vector<std::string> keys;	// object keys in order
	const Json& operator[](const std::string& k) const
	{
		static const Json missing;
		auto it = obj.find(k);
		return it == obj.end() ? missing : it->second;
	}
	bool has(const std::string& k) const { return obj.count(k) > 0; }
};

struct JsonParser
{
	const std::string& s;
	std::size_t i = 0;
	void ws()
	{
		while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) i++;
	}
	void expect(char c)
	{
		ws();
		if (i >= s.size() || s[i] != c) throw std::runtime_error(std::string("JSON: expected '") + c + "' at " + std::to_string(i));
		i++;
	}
	std::string string_literal()
	{
		expect('"');
		std::string out;
		while (i < s.size() && s[i] != '"')
		{
			if (s[i] == '\\')
			{
				i++;
				if (s[i] == 'u')
				{
					out += '?';
					i += 4;
				}
				else
					out += s[i] == 'n' ? '\n' : s[i];
				i++;
			}
			else
				out += s[i++];
		}
		expect('"');
		return out;
	}
	Json value()
	{
		ws();
		Json j;
		if (i >= s.size()) throw std::runtime_error("JSON: unexpected end");
		const char c = s[i];
		if (c == '{')
		{
			j.type = Json::Object;
			i++;
			ws();
			if (s[i] == '}')
			{
				i++;
				return j;
			}
			for (;;)
			{
				const std::string k = string_literal();
				expect(':');
				if (j.obj.count(k)) throw std::runtime_error("JSON: duplicate key " + k);
				j.obj[k] = value();
				j.keys.push_back(k);
				ws();
				if (s[i] == ',')
				{
					i++;
					continue;
				}
				expect('}');
				return j;
			}
		}
		if (c == '[')
		{
			j.type = Json::Array;
			i++;
			ws();
			if (s[i] == ']')
			{
				i++;
				return j;
			}
			for (;;)
			{
				j.arr.push_back(value());
				ws();
				if (s[i] == ',')
				{
					i++;
					continue;
				}
				expect(']');
				return j;
			}
		}
		if (c == '"')
		{
			j.type = Json::String;
			j.str = string_literal();
			return j;
		}
		for (const char* lit : {"null", "true", "false"})
			if (s.compare(i, std::strlen(lit), lit) == 0)
			{
				i += std::strlen(lit);
				j.type = lit[0] == 'n' ? Json::Null : Json::Bool;
				j.b = lit[0] == 't';
				return j;
			}
		std::size_t used = 0;
		j.num = std::stod(s.substr(i, 40), &used);
		if (used == 0) throw std::runtime_error("JSON: bad value at " + std::to_string(i));
		j.type = Json::Number;
		i += used;
		return j;
	}
};

Json parse_json(const std::string& text)
{
	JsonParser p{text};
	Json j = p.value();
	p.ws();
	if (p.i != text.size()) throw std::runtime_error("JSON: trailing text");
	return j;
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

TEST(RunGroundTruth, TooShortOrWrongColumnsAreErrorsNamingTheFile)
{
	const auto d = temp_dir();
	const std::string short_gt = (d / "short_gt.txt").string();
	{
		std::ofstream f(short_gt);
		f << "% x y z yaw pitch roll\n";
		for (int i = 0; i < 10; i++) f << i << " 0 0 0 0 0\n";
	}
	EXPECT_EQ(swba::eval::read_ground_truth_for(short_gt, 9).size(), 10u);  // exactly steps + 1 rows
	try
	{
		swba::eval::read_ground_truth_for(short_gt, 10);
		FAIL() << "no error";
	}
	catch (const std::runtime_error& e)
	{
		const std::string msg = e.what();
		EXPECT_NE(msg.find(short_gt), std::string::npos) << msg;
		EXPECT_NE(msg.find("10 rows, but the rawlog has 10 steps and needs 11 rows"), std::string::npos) << msg;
	}
	const std::string five = (d / "five_columns.txt").string();
	{
		std::ofstream f(five);
		f << "0 0 0 0 0 0\n1 0 0 0 0\n";
	}
	try
	{
		swba::eval::read_ground_truth_for(five, 1);
		FAIL() << "no error";
	}
	catch (const std::runtime_error& e)
	{
		const std::string msg = e.what();
		EXPECT_NE(msg.find(five), std::string::npos) << msg;
		EXPECT_NE(msg.find("6"), std::string::npos) << msg;
	}
}

TEST(RunSummaryJson, ShapeOfTheIssueExample)
{
	const RunReport rep = sample_report();
	const Json j = parse_json(swba::apps::format_summary_json(rep));
	ASSERT_EQ(j.type, Json::Object);
	EXPECT_EQ(j["rawlog"].str, rep.rawlog);
	EXPECT_EQ(j["steps"].num, 11.0);
	ASSERT_EQ(j["estimators"].type, Json::Array);
	ASSERT_EQ(j["estimators"].arr.size(), 4u);
	const std::vector<std::string> stats = {"rmse", "mean", "median", "max", "min", "sse", "std"};
	for (std::size_t i = 0; i < rep.rows.size(); i++)
	{
		const Json& e = j["estimators"].arr[i];
		const RunRow& r = rep.rows[i];
		for (const char* k : {"name", "window", "trajectory", "ape_trans", "ape_full", "seconds", "ms_per_step",
							  "policy", "fej", "method", "failed", "failure"})
			EXPECT_TRUE(e.has(k)) << r.label << ": no key " << k;
		EXPECT_EQ(e["name"].str, r.name);
		EXPECT_EQ(e["trajectory"].str, r.trajectory);
		if (r.name == "window")
		{
			EXPECT_EQ(e["window"].type, Json::Number);
			EXPECT_EQ(e["window"].num, 10.0);
			EXPECT_EQ(e["policy"].str, "slam");
			EXPECT_EQ(e["fej"].type, Json::Bool);
		}
		else
		{
			EXPECT_EQ(e["window"].type, Json::Null) << r.label;
			EXPECT_EQ(e["fej"].type, Json::Null) << r.label;
		}
		EXPECT_EQ(e["failed"].b, r.failed);
		if (r.has_ape)
		{
			for (const char* part : {"ape_trans", "ape_full"})
			{
				ASSERT_EQ(e[part].type, Json::Object);
				EXPECT_EQ(e[part].keys, stats) << part;
			}
			EXPECT_NEAR(e["ape_trans"]["rmse"].num, r.ape_trans.rmse, 1e-15);
			EXPECT_NEAR(e["ape_full"]["max"].num, r.ape_full.max, 1e-15);
			EXPECT_EQ(e["failure"].type, Json::Null);
		}
		else
		{
			EXPECT_EQ(e["ape_trans"].type, Json::Null);
			EXPECT_EQ(e["failure"].str, "Vehicle pose quaternion norm is not >0");
			EXPECT_EQ(e["failed_step"].num, 7.0);
			EXPECT_EQ(e["method"].str, "kfEKFNaive");
		}
		EXPECT_NEAR(e["ms_per_step"].num, r.ms_per_step, 1e-15);
	}
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
	EXPECT_EQ(columns, 10u + 14u + 2u);
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
	c.unconfirmed = 1;
	c.excluded = 6;
	c.down_weighted = 3;
	rep.rows[1].reading_counts = c;
	const Json j = parse_json(swba::apps::format_summary_json(rep));
	const Json& with = j["estimators"].arr[1];
	ASSERT_EQ(with["readings"].type, Json::Object);
	EXPECT_EQ(with["readings"].keys,
			  (std::vector<std::string>{"processed", "gated", "readmitted", "unconfirmed", "excluded", "down_weighted"}));
	EXPECT_EQ(with["readings"]["processed"].num, 100.0);
	EXPECT_EQ(with["readings"]["gated"].num, 7.0);
	EXPECT_EQ(with["readings"]["readmitted"].num, 2.0);
	EXPECT_EQ(with["readings"]["unconfirmed"].num, 1.0);
	EXPECT_EQ(with["readings"]["excluded"].num, 6.0);
	EXPECT_EQ(with["readings"]["down_weighted"].num, 3.0);
	EXPECT_EQ(j["estimators"].arr[0]["readings"].type, Json::Null);
}
