// g2o reader/writer: round trips, normalisation, skipped tags, malformed inputs with line numbers.
#include <swba/io/g2o.h>

#include <gtest/gtest.h>

#include <Eigen/Cholesky>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace
{
using swba::io::PoseGraph;

std::string data(const std::string& name) { return std::string(SWBA_DATA_DIR) + "/posegraph/" + name; }

PoseGraph read_text(const std::string& text)
{
	std::istringstream in(text);
	return swba::io::read_g2o(in, "test.g2o");
}

std::string write_text(const PoseGraph& g)
{
	std::ostringstream out;
	swba::io::write_g2o(g, out);
	return out.str();
}

/** Largest absolute difference between two graphs with the same structure (fails on a mismatch). */
double max_difference(const PoseGraph& a, const PoseGraph& b)
{
	EXPECT_EQ(a.vertices3.size(), b.vertices3.size());
	EXPECT_EQ(a.vertices2.size(), b.vertices2.size());
	EXPECT_EQ(a.edges3.size(), b.edges3.size());
	EXPECT_EQ(a.edges2.size(), b.edges2.size());
	EXPECT_EQ(a.fixed, b.fixed);
	double d = 0;
	const auto upd = [&](double x, double y) { d = std::max(d, std::abs(x - y)); };
	for (const auto& [id, v] : a.vertices3)
	{
		const auto it = b.vertices3.find(id);
		if (it == b.vertices3.end()) return 1e300;
		for (int i = 0; i < 3; i++) upd(v.t[i], it->second.t[i]);
		for (int i = 0; i < 4; i++) upd(v.q.coeffs()[i], it->second.q.coeffs()[i]);
	}
	for (const auto& [id, v] : a.vertices2)
	{
		const auto it = b.vertices2.find(id);
		if (it == b.vertices2.end()) return 1e300;
		upd(v.x, it->second.x), upd(v.y, it->second.y), upd(v.theta, it->second.theta);
	}
	for (size_t k = 0; k < std::min(a.edges3.size(), b.edges3.size()); k++)
	{
		const auto &e = a.edges3[k], &f = b.edges3[k];
		if (e.from != f.from || e.to != f.to) return 1e300;
		for (int i = 0; i < 3; i++) upd(e.t[i], f.t[i]);
		for (int i = 0; i < 4; i++) upd(e.q.coeffs()[i], f.q.coeffs()[i]);
		d = std::max(d, (e.information - f.information).cwiseAbs().maxCoeff());
	}
	for (size_t k = 0; k < std::min(a.edges2.size(), b.edges2.size()); k++)
	{
		const auto &e = a.edges2[k], &f = b.edges2[k];
		if (e.from != f.from || e.to != f.to) return 1e300;
		upd(e.x, f.x), upd(e.y, f.y), upd(e.theta, f.theta);
		d = std::max(d, (e.information - f.information).cwiseAbs().maxCoeff());
	}
	return d;
}

TEST(G2oReader, ReadsTheShippedGraphs)
{
	const auto sphere = swba::io::read_g2o(data("sphere2500.g2o"));
	EXPECT_EQ(sphere.vertices3.size(), 2500u);
	EXPECT_EQ(sphere.edges3.size(), 4949u);
	EXPECT_FALSE(sphere.is_2d());
	const auto garage = swba::io::read_g2o(data("parking-garage.g2o"));
	EXPECT_EQ(garage.vertices3.size(), 1661u);
	EXPECT_EQ(garage.edges3.size(), 6275u);
	const auto intel = swba::io::read_g2o(data("intel.g2o"));
	EXPECT_TRUE(intel.is_2d());
	EXPECT_EQ(intel.vertices2.size(), 1728u);
	EXPECT_EQ(intel.edges2.size(), 2512u);
	for (const auto* g : {&sphere, &garage})
		for (const auto& [id, v] : g->vertices3) ASSERT_NEAR(v.q.norm(), 1.0, 1e-15) << id;
	EXPECT_TRUE(sphere.skipped_tags.empty());
	// First edge of sphere2500, against the file's text (rotation information non-diagonal).
	const auto& e = sphere.edges3.front();
	EXPECT_EQ(e.from, 0);
	EXPECT_EQ(e.to, 1);
	EXPECT_EQ(e.t, Eigen::Vector3d(0.341895, -0.0416997, 0.0330394));
	EXPECT_EQ(e.information(3, 3), 400.021);
	EXPECT_EQ(e.information(3, 4), 0.00193512);
	EXPECT_EQ(e.information(5, 3), 2.06612);
	EXPECT_EQ(e.information(4, 5), 0.496977);
	EXPECT_EQ(e.information(5, 5), 99.203);
	EXPECT_EQ(e.information(0, 3), 0.0);
	// Edge quaternion normalised: (−0.00189341, 0.00395691, 0.0899835, 0.995934)/‖·‖.
	const double n = std::sqrt(0.00189341 * 0.00189341 + 0.00395691 * 0.00395691 + 0.0899835 * 0.0899835 +
							   0.995934 * 0.995934);
	EXPECT_NEAR(e.q.w(), 0.995934 / n, 1e-16);
	EXPECT_NEAR(e.q.norm(), 1.0, 1e-15);
	EXPECT_EQ(intel.edges2.front().information(1, 2), 185.36);
}

TEST(G2oReader, ReadWriteReadIsLosslessIn3dAnd2d)
{
	for (const char* name : {"smallGrid3D.g2o", "parking-garage.g2o", "intel.g2o"})
	{
		const auto g1 = swba::io::read_g2o(data(name));
		const std::string text1 = write_text(g1);
		const auto g2 = read_text(text1);
		EXPECT_LE(max_difference(g1, g2), 1e-12) << name;
		// Written text is a fixed point: a second round trip gives the same bytes.
		EXPECT_EQ(write_text(g2), text1) << name;
	}
}

TEST(G2oReader, ValuesMatchTheFileAndQuaternionsAreNormalised)
{
	const auto g = read_text(
		"# comment\n"
		"VERTEX_SE3:QUAT 0 1 2 3 0 0 0 2\n"
		"VERTEX_SE3:QUAT 5 -1.5 0.25 1e-3 0.1 0.2 0.3 0.9\n"
		"EDGE_SE3:QUAT 0 5 0.5 0.6 0.7 0 0 0 1  4 0.1 0 0 0 0  5 0 0 0 0  6 0 0 0  7 0 0  8 0  9\n"
		"FIX 5\n");
	ASSERT_EQ(g.vertices3.size(), 2u);
	EXPECT_NEAR(g.vertices3.at(0).q.w(), 1.0, 1e-16);
	EXPECT_EQ(g.vertices3.at(0).t, Eigen::Vector3d(1, 2, 3));
	const auto& q5 = g.vertices3.at(5).q;
	const double n = std::sqrt(0.01 + 0.04 + 0.09 + 0.81);
	EXPECT_NEAR(q5.x(), 0.1 / n, 1e-16);
	EXPECT_NEAR(q5.w(), 0.9 / n, 1e-16);
	ASSERT_EQ(g.edges3.size(), 1u);
	const auto& e = g.edges3[0];
	EXPECT_EQ(e.line, 4);
	EXPECT_EQ(e.information(0, 0), 4.0);
	EXPECT_EQ(e.information(0, 1), 0.1);
	EXPECT_EQ(e.information(1, 0), 0.1);
	EXPECT_EQ(e.information(1, 1), 5.0);
	EXPECT_EQ(e.information(5, 5), 9.0);
	EXPECT_EQ(g.fixed, std::set<swba::io::G2oId>{5});
}

TEST(G2oReader, Reads2dUpperTriangle)
{
	const auto g = read_text(
		"VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0.5\nEDGE_SE2 0 1 1 0 0.5 10 1 2 20 3 30\n");
	ASSERT_EQ(g.edges2.size(), 1u);
	Eigen::Matrix3d I;
	I << 10, 1, 2, 1, 20, 3, 2, 3, 30;
	EXPECT_EQ(g.edges2[0].information, I);
}

TEST(G2oReader, UnknownTagsAreSkippedAndCounted)
{
	const auto g = read_text(
		"PARAMS_SE3OFFSET 0 0 0 0 0 0 0 1\n"
		"VERTEX_SE3:QUAT 0 0 0 0 0 0 0 1\n"
		"VERTEX_XYZ 1 1 2 3\nVERTEX_XYZ 2 1 2 3\n");
	EXPECT_EQ(g.vertices3.size(), 1u);
	EXPECT_EQ(g.skipped_tags.at("VERTEX_XYZ"), 2);
	EXPECT_EQ(g.skipped_tags.at("PARAMS_SE3OFFSET"), 1);
	EXPECT_EQ(g.skipped_summary(), "skipped 3 line(s) with unknown tag(s): PARAMS_SE3OFFSET x1, VERTEX_XYZ x2");
}

/** Expects read_text to throw with a message containing every fragment. */
void expect_rejected(const std::string& text, const std::vector<std::string>& fragments)
{
	try
	{
		read_text(text);
		ADD_FAILURE() << "accepted:\n" << text;
	}
	catch (const std::runtime_error& e)
	{
		const std::string msg = e.what();
		for (const auto& f : fragments) EXPECT_NE(msg.find(f), std::string::npos) << "'" << f << "' not in: " << msg;
	}
}

const std::string kV0 = "VERTEX_SE3:QUAT 0 0 0 0 0 0 0 1\n";
const std::string kV1 = "VERTEX_SE3:QUAT 1 1 0 0 0 0 0 1\n";
const std::string kInfoId = " 1 0 0 0 0 0 1 0 0 0 0 1 0 0 0 1 0 0 1 0 1\n";

TEST(G2oReader, RejectsMalformedInputWithTheLine)
{
	expect_rejected(kV0 + "VERTEX_SE3:QUAT 1 1.0x 0 0 0 0 0 1\n", {"test.g2o:2:", "'1.0x'", "not a finite number"});
	expect_rejected(kV0 + kV1 + "EDGE_SE3:QUAT 0 1 1 0 0 0 0 0 1 1 0 0 0 0 0 1 0 nan 0 0 1 0 0 0 1 0 0 1 0 1\n",
					{"test.g2o:3:", "'nan'"});
	expect_rejected("VERTEX_SE3:QUAT one 0 0 0 0 0 0 1\n", {"test.g2o:1:", "not an integer vertex id"});
	// Missing vertex: reported at the edge's line, after the whole file was read.
	expect_rejected(kV0 + kV1 + "EDGE_SE3:QUAT 0 7 1 0 0 0 0 0 1" + kInfoId + kV0.substr(0, 0),
					{"test.g2o:3:", "vertex 7 is not defined"});
	// Not positive definite: entry (x,x) = −1. The message suggests the repair.
	expect_rejected(kV0 + kV1 + "EDGE_SE3:QUAT 0 1 1 0 0 0 0 0 1 -1 0 0 0 0 0 1 0 0 0 0 1 0 0 0 1 0 0 1 0 1\n",
					{"test.g2o:3:", "EDGE_SE3:QUAT", "information matrix is not positive definite",
					 "smallest eigenvalue -1", "use --information repair"});
	// Positive diagonal but indefinite (|off-diagonal| > diagonal).
	expect_rejected(kV0 + kV1 + "EDGE_SE2 0 1 1 0 0 1 5 0 1 0 1\n", {"test.g2o:3:"});
	// Truncated edge (information cut short).
	expect_rejected(kV0 + kV1 + "EDGE_SE3:QUAT 0 1 1 0 0 0 0 0 1 1 0 0 0\n",
					{"test.g2o:3:", "expected 30 fields", "found 13"});
	expect_rejected("VERTEX_SE2 0 0 0\n", {"test.g2o:1:", "expected 4 fields"});
	expect_rejected(kV0 + kV0, {"test.g2o:2:", "duplicate vertex id 0"});
	expect_rejected(kV0 + "VERTEX_SE3:QUAT 1 0 0 0 0 0 0 0\n", {"test.g2o:2:", "zero norm"});
	expect_rejected(kV0 + "VERTEX_SE2 1 0 0 0\n", {"test.g2o:2:", "mix 2D and 3D"});
	expect_rejected(kV0 + "\n\nFIX 3\n", {"test.g2o:4:", "FIX", "vertex 3 is not defined"});
	expect_rejected(kV0 + kV1 + "EDGE_SE3:QUAT 1 1 1 0 0 0 0 0 1" + kInfoId, {"test.g2o:3:", "itself"});
}

// --information repair (InformationPolicy::Repair): indefinite informations replaced and counted.
PoseGraph read_repaired(const std::string& text)
{
	std::istringstream in(text);
	swba::io::G2oReadOptions o;
	o.information = swba::io::InformationPolicy::Repair;
	return swba::io::read_g2o(in, "test.g2o", o);
}

TEST(G2oReader, RepairReplacesAnIndefiniteSe3InformationAndCountsIt)
{
	// Line 4: diag(−1, 1, 1, 1, 1, 1) → diag(1e-6, 1, 1, 1, 1, 1); line 3 is valid and kept bit for bit.
	const std::string valid = "EDGE_SE3:QUAT 0 1 1 0 0 0 0 0 1 4 0.5 0 0 0 0 3 0 0 0 0 2 0 0 0 1 0 0 1 0 1\n";
	const std::string text =
		kV0 + kV1 + valid + "EDGE_SE3:QUAT 1 0 -1 0 0 0 0 0 1 -1 0 0 0 0 0 1 0 0 0 0 1 0 0 0 1 0 0 1 0 1\n";
	const PoseGraph g = read_repaired(text);
	ASSERT_EQ(g.edges3.size(), 2u);
	EXPECT_EQ(g.repaired_information.count, 1);
	EXPECT_EQ(g.repaired_information.lines, (std::vector<int>{4}));
	EXPECT_EQ(g.repaired_information.min_eigenvalue, -1);
	EXPECT_EQ(g.repaired_information.min_eigenvalue_line, 4);
	EXPECT_EQ(g.edges3[0].information, read_text(kV0 + kV1 + valid).edges3[0].information);
	Eigen::Matrix<double, 6, 1> expected;
	expected << 1e-6, 1, 1, 1, 1, 1;
	EXPECT_TRUE(g.edges3[1].information.isApprox(Eigen::Matrix<double, 6, 6>(expected.asDiagonal()), 1e-12));
	using Llt6 = Eigen::LLT<Eigen::Matrix<double, 6, 6>>;
	EXPECT_EQ(Llt6(g.edges3[1].information).info(), Eigen::Success);
	EXPECT_EQ(g.repaired_information.summary(g.num_edges(), swba::kPositiveDefiniteRelativeFloor),
			  "repaired 1 of 2 edge information matrices (not positive definite; eigenvalues below 1e-06 x the "
			  "largest raised to it; most negative eigenvalue -1 at line 4)");
	// The default (strict) refuses the same file.
	expect_rejected(text, {"test.g2o:4:", "use --information repair"});
}

TEST(G2oReader, RepairReplacesAnIndefiniteSe2Information)
{
	const std::string v2 = "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\n";
	// (x, y) block [[1, 5], [5, 1]]: eigenvalues 6 and −4.
	const PoseGraph g = read_repaired(v2 + "EDGE_SE2 0 1 1 0 0 1 5 0 1 0 1\n");
	EXPECT_EQ(g.repaired_information.count, 1);
	EXPECT_EQ(g.repaired_information.min_eigenvalue_line, 3);
	EXPECT_NEAR(g.repaired_information.min_eigenvalue, -4, 1e-12);
	EXPECT_EQ(Eigen::LLT<Eigen::Matrix3d>(g.edges2[0].information).info(), Eigen::Success);
	// A valid file: nothing repaired, and the summary says so.
	const PoseGraph ok = read_repaired(v2 + "EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\n");
	EXPECT_EQ(ok.repaired_information.count, 0);
	EXPECT_EQ(ok.repaired_information.summary(1, 1e-6),
			  "repaired 0 of 1 edge information matrices (all positive definite)");
}

TEST(G2oReader, RepairRefusesAnInformationWithoutPositiveEigenvalue)
{
	const std::string v2 = "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\n";
	try
	{
		read_repaired(v2 + "EDGE_SE2 0 1 1 0 0 -1 0 0 -1 0 0\n");
		FAIL() << "no exception";
	}
	catch (const std::runtime_error& e)
	{
		const std::string msg = e.what();
		for (const char* f : {"test.g2o:3:", "EDGE_SE2", "cannot be repaired", "no positive eigenvalue"})
			EXPECT_NE(msg.find(f), std::string::npos) << "'" << f << "' not in: " << msg;
	}
}

TEST(G2oReader, MissingFileIsAnError)
{
	EXPECT_THROW(swba::io::read_g2o("/nonexistent/graph.g2o"), std::runtime_error);
}

// A malformed field is quoted by its first 40 characters, never whole (a 1 MB token made a 1 MB message);
// an unknown tag likewise in the skipped-lines warning.
TEST(G2oReader, LongFieldsAndTagsAreQuotedShort)
{
	const std::string field = std::string(1000000, '1') + "x";
	try
	{
		read_text("VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 " + field + " 0 0\n");
		ADD_FAILURE() << "accepted";
	}
	catch (const std::runtime_error& e)
	{
		const std::string msg = e.what();
		EXPECT_EQ(msg, "test.g2o:2: VERTEX_SE2: field 2 ('" + std::string(40, '1') + "...') is not a finite number");
	}
	const auto g = read_text("VERTEX_SE2 0 0 0 0\n" + std::string(100000, 'T') + " 1 0 0\n");
	EXPECT_EQ(g.skipped_summary(), "skipped 1 line(s) with unknown tag(s): " + std::string(40, 'T') + "... x1");
}

// A graph with a non-finite vertex value is never written (the reader would refuse it), to a file or a stream.
TEST(G2oWriter, RefusesNonFiniteVertexValues)
{
	PoseGraph g = read_text("VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\n");
	g.vertices2.at(1).y = std::nan("");
	const std::string path = ::testing::TempDir() + "swba_g2o_non_finite.g2o";
	std::remove(path.c_str());
	try
	{
		swba::io::write_g2o(g, path);
		ADD_FAILURE() << "written";
	}
	catch (const std::runtime_error& e)
	{
		const std::string msg = e.what();
		EXPECT_NE(msg.find("g2o file '" + path + "' not written: vertex 1 (x y theta = 1 nan 0) is not finite"),
				  std::string::npos)
			<< msg;
	}
	EXPECT_FALSE(std::ifstream(path).good());
	EXPECT_THROW(write_text(g), std::runtime_error);
	g = read_text(kV0 + kV1);
	g.vertices3.at(0).t.x() = HUGE_VAL;
	EXPECT_THROW(write_text(g), std::runtime_error);
}
}  // namespace
