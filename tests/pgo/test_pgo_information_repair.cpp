// `swba pgo --information repair` in-process (swba/apps/pgo.h): a 3D loop whose loop-closure edge
// has an indefinite information is refused by default, with a hint, and solved with the repair.
#include <swba/apps/pgo.h>

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <stdexcept>

namespace
{
// 6×6 upper triangles, row by row: diag(100, …) and the same with 300 at (qx, qy), whose
// (qx, qy) block [[100, 300], [300, 100]] has eigenvalues 400 and −200.
const std::string kInfo = " 100 0 0 0 0 0 100 0 0 0 0 100 0 0 0 100 0 0 100 0 100\n";
const std::string kIndefinite = " 100 0 0 0 0 0 100 0 0 0 0 100 0 0 0 100 300 0 100 0 100\n";

/** A unit square loop, slightly inconsistent measurements; the loop closure (line 8) indefinite. */
std::string write_loop()
{
	const std::string path = ::testing::TempDir() + "swba_pgo_indefinite_loop.g2o";
	std::ofstream out(path);
	out << "VERTEX_SE3:QUAT 0 0 0 0 0 0 0 1\nVERTEX_SE3:QUAT 1 1 0 0 0 0 0 1\n"
		<< "VERTEX_SE3:QUAT 2 1 1 0 0 0 0 1\nVERTEX_SE3:QUAT 3 0 1 0 0 0 0 1\n"
		<< "EDGE_SE3:QUAT 0 1 1.01 0 0 0 0 0 1" << kInfo << "EDGE_SE3:QUAT 1 2 0 0.99 0.01 0 0 0 1" << kInfo
		<< "EDGE_SE3:QUAT 2 3 -1 0.02 0 0 0 0.01 1" << kInfo << "EDGE_SE3:QUAT 3 0 0 -1.01 0 0 0 0 1" << kIndefinite;
	return path;
}

swba::apps::PgoAppOptions options(const std::string& path)
{
	swba::apps::PgoAppOptions o;
	o.input_path = path;
	o.solver.progress_to_stdout = false;
	return o;
}

TEST(PgoInformationRepair, StrictRefusesWithFileLineAndTheHint)
{
	const std::string path = write_loop();
	std::ostringstream out, log;
	try
	{
		swba::apps::run_pgo_app(options(path), out, log);
		FAIL() << "accepted";
	}
	catch (const std::runtime_error& e)
	{
		const std::string msg = e.what();
		for (const std::string& f : {path + ":8: EDGE_SE3:QUAT: information matrix is not positive definite",
									std::string("smallest eigenvalue -200"),
									std::string("use --information repair to replace it by the nearest positive-definite matrix")})
			EXPECT_NE(msg.find(f), std::string::npos) << "'" << f << "' not in: " << msg;
	}
}

TEST(PgoInformationRepair, RepairLoadsCountsAndSolves)
{
	const std::string path = write_loop();
	auto o = options(path);
	o.read.information = swba::io::InformationPolicy::Repair;
	std::ostringstream out, log;
	const auto r = swba::apps::run_pgo_app(o, out, log);
	EXPECT_EQ(r.repaired_information, 1);
	EXPECT_NE(log.str().find("swba pgo: repaired 1 of 4 edge information matrices (not positive definite;"),
			  std::string::npos)
		<< log.str();
	EXPECT_NE(out.str().find("4 edges (3D SE3:QUAT), 0 FIX, 1 information matrices repaired\n"), std::string::npos)
		<< out.str();
	EXPECT_TRUE(r.summary.is_solution_usable()) << r.summary.message;
	EXPECT_LT(r.summary.final_cost, r.summary.initial_cost);
	// The residual misclosure is ≈ 0.01–0.02 per axis on 4 edges of weight 100: the cost is of order 0.1.
	EXPECT_LT(r.summary.final_cost, 1.0);
}

TEST(PgoInformationRepair, PolicyNamesComeFromOneTable)
{
	using swba::io::InformationPolicy;
	EXPECT_EQ(swba::parse_enum<InformationPolicy>("strict", "information policy"), InformationPolicy::Strict);
	EXPECT_EQ(swba::parse_enum<InformationPolicy>("repair", "information policy"), InformationPolicy::Repair);
	EXPECT_EQ(swba::enum_choices<InformationPolicy>("|"), "strict|repair");
	EXPECT_THROW(swba::parse_enum<InformationPolicy>("clip", "information policy"), std::invalid_argument);
}
}  // namespace
