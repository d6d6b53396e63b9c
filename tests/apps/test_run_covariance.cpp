// swba run's covariance files: one beside every TUM file with one line of 28 numbers per TUM row (same
// stamps), the landmarks file, covariance_seconds in summary.json; planar rows embed SE(2).
#include <swba/apps/run.h>
#include <swba/io/rawlog.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace
{
namespace fs = std::filesystem;

std::vector<std::vector<double>> read_rows(const fs::path& p)
{
	std::vector<std::vector<double>> rows;
	std::ifstream f(p);
	std::string line;
	while (std::getline(f, line))
	{
		std::istringstream s(line);
		std::vector<double> v;
		double x;
		while (s >> x) v.push_back(x);
		rows.push_back(v);
	}
	return rows;
}

/** Runs every estimator on the first `steps` steps of `rawlog` and writes the files into a fresh directory. */
swba::apps::RunReport run_and_write(const std::string& rawlog, std::size_t steps, const std::string& dir)
{
	swba::apps::RunOptions o;
	o.out_dir = (fs::temp_directory_path() / dir).string();
	fs::remove_all(o.out_dir);
	fs::create_directories(o.out_dir);
	o.windows = {5};
	o.plots = false;
	o.progress = false;
	swba::io::RawlogReaderOptions ro;
	ro.max_steps = steps;
	const swba::io::Rawlog log = swba::io::read_rawlog(std::string(SWBA_MRPT_DATASETS) + "/" + rawlog, ro);
	std::ostringstream sink;
	swba::apps::RunReport rep = swba::apps::run_estimators(o, log, {}, sink);
	rep.steps = log.steps.size();
	swba::apps::write_run_files(o, {}, rep);
	return rep;
}

/** Checks every row's files; returns the rows of the covariance files by TUM file name. */
std::map<std::string, std::vector<std::vector<double>>> check_files(const swba::apps::RunReport& rep, const fs::path& dir)
{
	std::map<std::string, std::vector<std::vector<double>>> out;
	int rows_with_files = 0;
	for (const auto& r : rep.rows)
	{
		if (r.file.empty()) continue;
		rows_with_files++;
		const std::string stem = r.file.substr(0, r.file.size() - 4);
		const auto tum = read_rows(dir / r.file);
		const auto cov = read_rows(dir / (stem + ".cov"));
		const auto lms = read_rows(dir / (stem + "_landmarks.cov"));
		EXPECT_EQ(cov.size(), tum.size()) << r.file;
		for (std::size_t i = 0; i < cov.size() && i < tum.size(); i++)
		{
			EXPECT_EQ(cov[i].size(), 28u) << stem << " line " << i + 1;
			EXPECT_EQ(cov[i][0], tum[i][0]) << stem << " line " << i + 1;
		}
		EXPECT_FALSE(lms.empty()) << stem;
		for (const auto& l : lms) EXPECT_EQ(l.size(), 10u) << stem;
		out[r.file] = cov;
	}
	EXPECT_EQ(rows_with_files, 6);  // two EKF methods, window online and lagged, batch from two starts
	return out;
}
}  // namespace

TEST(RunCovariance, EveryRowWritesItsCovarianceFiles)
{
	const auto rep = run_and_write("kf-slam_6D_demo.rawlog", 20, "swba_test_run_covariance");
	const fs::path dir = fs::temp_directory_path() / "swba_test_run_covariance";
	const auto files = check_files(rep, dir);
	// Position covariance (world) and the pose's ρρ block have the same trace (a rotation apart).
	for (const auto& [file, rows] : files)
		for (const auto& c : rows)
		{
			if (c.size() != 28) continue;  // reported by check_files
			EXPECT_NEAR(c[1] + c[4] + c[6], c[7] + c[13] + c[18], 1e-12 + 1e-7 * (c[7] + c[13] + c[18])) << file;
		}
	std::ifstream f(dir / "summary.json");
	const auto j = nlohmann::json::parse(f);
	for (const auto& e : j["estimators"])
	{
		if (e["name"] == "ekf")
		{
			EXPECT_TRUE(e["covariance_seconds"].is_null());
		}
		else
		{
			EXPECT_GT(e["covariance_seconds"].get<double>(), 0) << e["label"];
		}
	}
	fs::remove_all(dir);
}

TEST(RunCovariance, PlanarRowsEmbedTheSe2CovarianceWithZeroOffPlaneEntries)
{
	const auto rep = run_and_write("kf-slam_demo.rawlog", 20, "swba_test_run_covariance_2d");
	const fs::path dir = fs::temp_directory_path() / "swba_test_run_covariance_2d";
	const auto files = check_files(rep, dir);
	// Upper-triangle index of (i, j), i ≤ j, in the 21 entries after the stamp and the 6 position ones.
	const auto at = [](int i, int j) { return 7 + i * 6 - i * (i - 1) / 2 + (j - i); };
	for (const auto& [file, rows] : files)
		for (const auto& c : rows)
		{
			if (c.size() != 28) continue;  // reported by check_files
			for (int i = 0; i < 6; i++)
				for (int j = i; j < 6; j++)
				{
					const bool planar = (i == 0 || i == 1 || i == 5) && (j == 0 || j == 1 || j == 5);
					if (!planar)
					{
						EXPECT_EQ(c[at(i, j)], 0.0) << file << " (" << i << ", " << j << ")";
					}
				}
			if (c[0] > 1.5)  // the EKF is still at its exact start after the first step
			{
				EXPECT_GT(c[at(0, 0)], 0) << file;
				EXPECT_GT(c[at(5, 5)], 0) << file;
			}
			EXPECT_EQ(c[3], 0.0) << file;  // position xz
			EXPECT_EQ(c[6], 0.0) << file;  // position zz
		}
	fs::remove_all(dir);
}
