// g2o pose-graph reader and writer.
#include <swba/io/g2o.h>

#include <swba/core/file.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>

namespace swba::io
{
namespace
{
constexpr const char* kVertex3 = "VERTEX_SE3:QUAT";
constexpr const char* kEdge3 = "EDGE_SE3:QUAT";
constexpr const char* kVertex2 = "VERTEX_SE2";
constexpr const char* kEdge2 = "EDGE_SE2";
constexpr const char* kFix = "FIX";

using Tokens = std::vector<std::string>;

/** A field or tag as error messages quote it: '<text>', cut to its first 40 characters ("...") so that a
 * 20 MB token does not become a 20 MB message. */
std::string g2o_quoted(const std::string& t)
{
	return "'" + (t.size() > 40 ? t.substr(0, 40) + "..." : t) + "'";
}

/** Parsing context of one line: error messages carry "<source>:<line>: <tag>: ". */
struct LineContext
{
	const std::string& source;
	int line;
	const std::string& tag;

	[[noreturn]] void fail(const std::string& why) const
	{
		throw std::runtime_error(source + ":" + std::to_string(line) + ": " + tag + ": " + why);
	}
	void expect_fields(const Tokens& tok, size_t n, const char* layout) const
	{
		if (tok.size() - 1 != n)
			fail("expected " + std::to_string(n) + " fields (" + layout + "), found " +
				 std::to_string(tok.size() - 1));
	}
	/** Field i read whole by `read` (std::strtod or std::strtoll's signature), in range and finite (as
	 * a double: always, for an integer); otherwise fails "field i ('text') is not <what>" (the text cut to
	 * 40 characters). */
	template <class Read>
	auto whole_field(const Tokens& tok, size_t i, Read read, const char* what) const
	{
		const char* s = tok[i].c_str();
		char* end = nullptr;
		errno = 0;
		const auto v = read(s, &end);
		if (end == s || *end != '\0' || errno == ERANGE || !std::isfinite(static_cast<double>(v)))
			fail("field " + std::to_string(i) + " (" + g2o_quoted(tok[i]) + ") is not " + what);
		return v;
	}
	double number(const Tokens& tok, size_t i) const
	{
		return whole_field(tok, i, [](const char* s, char** end) { return std::strtod(s, end); }, "a finite number");
	}
	G2oId id(const Tokens& tok, size_t i) const
	{
		const auto read = [](const char* s, char** end) { return std::strtoll(s, end, 10); };
		return static_cast<G2oId>(whole_field(tok, i, read, "an integer vertex id"));
	}
	/** The vertex ids of an edge (fields 1 and 2, distinct) and its source line. */
	template <typename Edge>
	void edge_ends(const Tokens& tok, Edge& e) const
	{
		e.from = id(tok, 1);
		e.to = id(tok, 2);
		if (e.from == e.to) fail("edge connects vertex " + std::to_string(e.from) + " to itself");
		e.line = line;
	}
	Eigen::Quaterniond quaternion(const Tokens& tok, size_t first) const
	{
		Eigen::Quaterniond q(number(tok, first + 3), number(tok, first), number(tok, first + 1),
							 number(tok, first + 2));
		const double n = q.norm();
		if (!(n > 1e-12)) fail("quaternion has zero norm");
		// Already unit to rounding: left as is, so that normalising is idempotent and a written
		// graph reads back bit for bit.
		if (std::abs(n - 1.0) > 1e-15) q.coeffs() /= n;
		return q;
	}
	/** Reads the upper triangle (row by row) of an n×n information matrix (symmetric by construction). */
	template <int N>
	Eigen::Matrix<double, N, N> information(const Tokens& tok, size_t first) const
	{
		Eigen::Matrix<double, N, N> I;
		size_t k = first;
		for (int r = 0; r < N; r++)
			for (int c = r; c < N; c++) I(r, c) = I(c, r) = number(tok, k++);
		return I;
	}
};


/** Reads a file line by line. Vertex references (edges, FIX) are resolved by finish(), after the
 * whole file: an element may come before the vertices it names. */
class G2oFileReader
{
   public:
	G2oFileReader(const std::string& source, const G2oReadOptions& options) : source_(source), options_(options) {}

	/** One non-blank, non-comment line split into fields (`tok[0]` is the tag). */
	void read_line(const Tokens& tok, int line_no)
	{
		const std::string& tag = tok[0];
		const LineContext ctx{source_, line_no, tag};
		if (tag == kVertex3) read_vertex3(ctx, tok);
		else if (tag == kEdge3) read_edge3(ctx, tok);
		else if (tag == kVertex2) read_vertex2(ctx, tok);
		else if (tag == kEdge2) read_edge2(ctx, tok);
		else if (tag == kFix)
		{
			if (tok.size() < 2) ctx.fail("expected at least one vertex id");
			for (size_t i = 1; i < tok.size(); i++) fix_lines_.emplace_back(ctx.id(tok, i), line_no);
		}
		else
			g_.skipped_tags[tag]++;
	}

	/** Checks that every edge and FIX line names a defined vertex; returns the graph. */
	PoseGraph finish()
	{
		for (const auto& e : g_.edges3) check_vertices(e.from, e.to, e.line, kEdge3);
		for (const auto& e : g_.edges2) check_vertices(e.from, e.to, e.line, kEdge2);
		for (const auto& [id, ln] : fix_lines_)
		{
			if (!has_vertex(id))
				throw std::runtime_error(source_ + ":" + std::to_string(ln) + ": FIX: vertex " + std::to_string(id) +
										 " is not defined");
			g_.fixed.insert(id);
		}
		return std::move(g_);
	}

   private:
	enum class Kind
	{
		Unknown,
		Two,
		Three
	};

	void set_kind(const LineContext& ctx, Kind k)
	{
		if (kind_ != Kind::Unknown && kind_ != k) ctx.fail("a file may not mix 2D and 3D elements");
		kind_ = k;
	}
	/** A vertex line: `layout` names the fields after the tag; `make()` reads the pose (fields 2…). */
	template <typename Vertex, typename Make>
	void read_vertex(const LineContext& ctx, const Tokens& tok, Kind kind, size_t fields, const char* layout,
					 std::map<G2oId, Vertex>& vertices, Make make)
	{
		set_kind(ctx, kind);
		ctx.expect_fields(tok, fields, layout);
		const G2oId id = ctx.id(tok, 1);
		if (!vertices.emplace(id, make()).second) ctx.fail("duplicate vertex id " + std::to_string(id));
	}
	/** An edge line: the vertex ids, the measurement (`fill`, fields 3…), then the N×N information
	 * matrix from field `info_first`. */
	template <int N, typename Edge, typename Fill>
	void read_edge(const LineContext& ctx, const Tokens& tok, Kind kind, size_t fields, const char* layout,
				   size_t info_first, std::vector<Edge>& edges, Fill fill)
	{
		set_kind(ctx, kind);
		ctx.expect_fields(tok, fields, layout);
		Edge e;
		ctx.edge_ends(tok, e);
		fill(e);
		e.information = ctx.information<N>(tok, info_first);
		check_information(ctx, e.information);
		edges.push_back(e);
	}
	/** A positive-definite information (Cholesky succeeds) is kept bit for bit. Otherwise: Strict
	 * refuses, naming the smallest eigenvalue and the repair option; Repair replaces it by the nearest
	 * positive-definite matrix and records it in g_.repaired_information. */
	template <int N>
	void check_information(const LineContext& ctx, Eigen::Matrix<double, N, N>& info)
	{
		if (Eigen::LLT<Eigen::Matrix<double, N, N>>(info).info() == Eigen::Success) return;
		char buf[64];
		if (options_.information == InformationPolicy::Strict)
		{
			const double min_eig = Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, N, N>>(info, Eigen::EigenvaluesOnly)
									   .eigenvalues()(0);
			std::snprintf(buf, sizeof buf, "%.6g", min_eig);
			ctx.fail(std::string("information matrix is not positive definite (smallest eigenvalue ") + buf +
					 "); use --information repair to replace it by the nearest positive-definite matrix");
		}
		PositiveDefiniteRepair r;
		try
		{
			r = repair_positive_definite(info, options_.relative_floor);
		}
		catch (const std::domain_error& e)
		{
			ctx.fail(std::string("information matrix is not positive definite and cannot be repaired: ") + e.what());
		}
		info = r.matrix;
		InformationRepairs& rep = g_.repaired_information;
		if (rep.count == 0 || r.min_eigenvalue < rep.min_eigenvalue)
		{
			rep.min_eigenvalue = r.min_eigenvalue;
			rep.min_eigenvalue_line = ctx.line;
		}
		rep.count++;
		rep.lines.push_back(ctx.line);
	}
	void read_vertex3(const LineContext& ctx, const Tokens& tok)
	{
		read_vertex(ctx, tok, Kind::Three, 8, "id x y z qx qy qz qw", g_.vertices3, [&] {
			PoseGraphVertex3 v;
			v.t = Eigen::Vector3d(ctx.number(tok, 2), ctx.number(tok, 3), ctx.number(tok, 4));
			v.q = ctx.quaternion(tok, 5);
			return v;
		});
	}
	void read_vertex2(const LineContext& ctx, const Tokens& tok)
	{
		read_vertex(ctx, tok, Kind::Two, 4, "id x y theta", g_.vertices2, [&] {
			return PoseGraphVertex2{ctx.number(tok, 2), ctx.number(tok, 3), ctx.number(tok, 4)};
		});
	}
	void read_edge3(const LineContext& ctx, const Tokens& tok)
	{
		read_edge<6>(ctx, tok, Kind::Three, 30, "i j x y z qx qy qz qw + 21 information entries", 10, g_.edges3,
					 [&](PoseGraphEdge3& e) {
						 e.t = Eigen::Vector3d(ctx.number(tok, 3), ctx.number(tok, 4), ctx.number(tok, 5));
						 e.q = ctx.quaternion(tok, 6);
					 });
	}
	void read_edge2(const LineContext& ctx, const Tokens& tok)
	{
		read_edge<3>(ctx, tok, Kind::Two, 11, "i j x y theta + 6 information entries", 6, g_.edges2,
					 [&](PoseGraphEdge2& e) {
						 e.x = ctx.number(tok, 3);
						 e.y = ctx.number(tok, 4);
						 e.theta = ctx.number(tok, 5);
					 });
	}
	bool has_vertex(G2oId id) const { return g_.vertices3.count(id) || g_.vertices2.count(id); }
	void check_vertices(G2oId from, G2oId to, int line, const char* tag) const
	{
		for (G2oId id : {from, to})
			if (!has_vertex(id))
				throw std::runtime_error(source_ + ":" + std::to_string(line) + ": " + tag + ": vertex " +
										 std::to_string(id) + " is not defined");
	}

	const std::string& source_;
	const G2oReadOptions& options_;
	PoseGraph g_;
	std::vector<std::pair<G2oId, int>> fix_lines_;  ///< (id, line) of every FIX entry
	Kind kind_ = Kind::Unknown;
};

void put(std::ostream& out, double v)
{
	char buf[40];
	std::snprintf(buf, sizeof buf, " %.17g", v);
	out << buf;
}
}  // namespace

std::string PoseGraph::skipped_summary() const
{
	if (skipped_tags.empty()) return {};
	int total = 0;
	std::string list;
	for (const auto& [tag, n] : skipped_tags)
	{
		total += n;
		list += (list.empty() ? "" : ", ") + (tag.size() > 40 ? tag.substr(0, 40) + "..." : tag) + " x" + std::to_string(n);
	}
	return "skipped " + std::to_string(total) + " line(s) with unknown tag(s): " + list;
}

std::string PoseGraph::first_non_finite_vertex() const
{
	char buf[200];
	for (const auto& [id, v] : vertices2)
		if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.theta))
		{
			std::snprintf(buf, sizeof buf, "vertex %lld (x y theta = %g %g %g)", static_cast<long long>(id), v.x, v.y,
						  v.theta);
			return buf;
		}
	for (const auto& [id, v] : vertices3)
		if (!v.t.allFinite() || !v.q.coeffs().allFinite())
		{
			std::snprintf(buf, sizeof buf, "vertex %lld (x y z = %g %g %g, qx qy qz qw = %g %g %g %g)",
						  static_cast<long long>(id), v.t.x(), v.t.y(), v.t.z(), v.q.x(), v.q.y(), v.q.z(), v.q.w());
			return buf;
		}
	return "";
}

std::string InformationRepairs::summary(size_t num_edges, double relative_floor) const
{
	char buf[200];
	std::snprintf(buf, sizeof buf, "repaired %d of %zu edge information matrices", count, num_edges);
	std::string s = buf;
	if (count == 0) return s + " (all positive definite)";
	std::snprintf(buf, sizeof buf,
				  " (not positive definite; eigenvalues below %g x the largest raised to it; most negative "
				  "eigenvalue %.6g at line %d)",
				  relative_floor, min_eigenvalue, min_eigenvalue_line);
	return s + buf;
}

PoseGraph read_g2o(const std::string& path, const G2oReadOptions& options)
{
	std::ifstream in = open_input_file(path, std::ios::in | std::ios::binary, "g2o file");
	if (const std::string note = binary_data_note(in); !note.empty())
		throw std::runtime_error("g2o file '" + path + "': " + note);
	return read_g2o(in, path, options);
}

PoseGraph read_g2o(std::istream& in, const std::string& source_name, const G2oReadOptions& options)
{
	if (!(options.relative_floor > 0 && options.relative_floor <= 1))
		throw std::invalid_argument("read_g2o: relative_floor must be in (0, 1]");
	G2oFileReader reader(source_name, options);
	std::string line;
	for (int line_no = 1; std::getline(in, line); line_no++)
	{
		std::istringstream ss(line);
		const Tokens tok{std::istream_iterator<std::string>(ss), std::istream_iterator<std::string>()};
		if (!tok.empty() && tok[0][0] != '#') reader.read_line(tok, line_no);
	}
	if (in.bad()) throw std::runtime_error(source_name + ": read error");
	return reader.finish();
}

void write_g2o(const PoseGraph& g, const std::string& path)
{
	if (const std::string bad = g.first_non_finite_vertex(); !bad.empty())
		throw std::runtime_error("g2o file '" + path + "' not written: " + bad + " is not finite");
	write_file_atomically(path, [&](std::ostream& out) { write_g2o(g, out); });
}

void write_g2o(const PoseGraph& g, std::ostream& out)
{
	// Never a graph that would not read back: the reader refuses non-finite values.
	if (const std::string bad = g.first_non_finite_vertex(); !bad.empty())
		throw std::runtime_error("write_g2o: " + bad + " is not finite");
	for (const auto& [id, v] : g.vertices3)
	{
		out << kVertex3 << ' ' << id;
		for (int i = 0; i < 3; i++) put(out, v.t[i]);
		for (int i = 0; i < 4; i++) put(out, v.q.coeffs()[i]);  // x y z w
		out << '\n';
	}
	for (const auto& [id, v] : g.vertices2)
	{
		out << kVertex2 << ' ' << id;
		put(out, v.x);
		put(out, v.y);
		put(out, v.theta);
		out << '\n';
	}
	for (const auto& e : g.edges3)
	{
		out << kEdge3 << ' ' << e.from << ' ' << e.to;
		for (int i = 0; i < 3; i++) put(out, e.t[i]);
		for (int i = 0; i < 4; i++) put(out, e.q.coeffs()[i]);
		for (int r = 0; r < 6; r++)
			for (int c = r; c < 6; c++) put(out, e.information(r, c));
		out << '\n';
	}
	for (const auto& e : g.edges2)
	{
		out << kEdge2 << ' ' << e.from << ' ' << e.to;
		put(out, e.x);
		put(out, e.y);
		put(out, e.theta);
		for (int r = 0; r < 3; r++)
			for (int c = r; c < 3; c++) put(out, e.information(r, c));
		out << '\n';
	}
	for (G2oId id : g.fixed) out << kFix << ' ' << id << '\n';
}
}  // namespace swba::io
