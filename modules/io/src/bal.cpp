#include <swba/io/bal.h>

#include <swba/core/file.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string_view>

#ifdef SWBA_HAVE_BZIP2
#include <bzlib.h>
#endif

namespace swba::io
{
BalParseError::BalParseError(const std::string& source, int line, const std::string& reason)
	: std::runtime_error(source + ":" + std::to_string(line) + ": " + reason), line_(line)
{
}

namespace
{
/** Splits the text into whitespace-separated tokens and keeps track of line numbers. */
class Scanner
{
   public:
	explicit Scanner(const std::string& text) : p_(text.data()), end_(text.data() + text.size()) {}

	/** Next token on any line; false at the end of the text. `line` is the token's line. */
	bool next(std::string_view& token, int& line)
	{
		skip_space(true);
		if (p_ == end_) return false;
		line = line_;
		token = take_token();
		return true;
	}

	/** All tokens of the next non-blank line; false at the end of the text. */
	bool next_line(std::vector<std::string_view>& tokens, int& line)
	{
		tokens.clear();
		skip_space(true);
		if (p_ == end_) return false;
		line = line_;
		while (p_ != end_ && *p_ != '\n')
		{
			tokens.push_back(take_token());
			skip_space(false);
		}
		return true;
	}

	/** Line of the current position (after the last token read). */
	int line() const { return line_; }

   private:
	static bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }
	void skip_space(bool newlines)
	{
		while (p_ != end_ && (is_space(*p_) || (newlines && *p_ == '\n')))
		{
			if (*p_ == '\n') line_++;
			p_++;
		}
	}
	std::string_view take_token()
	{
		const char* b = p_;
		while (p_ != end_ && !is_space(*p_) && *p_ != '\n') p_++;
		return std::string_view(b, static_cast<size_t>(p_ - b));
	}

	const char* p_;
	const char* end_;
	int line_ = 1;
};

std::string quoted(std::string_view t)
{
	std::string s(t.substr(0, 40));
	if (t.size() > 40) s += "...";
	return "'" + s + "'";
}

class Parser
{
   public:
	Parser(const std::string& text, std::string source)
		: scan_(text), source_(std::move(source)), text_size_(text.size())
	{
	}

	BalProblem parse()
	{
		BalProblem bal;
		const int num_obs = parse_header(bal);
		parse_observations(num_obs, bal);
		parse_parameters(bal);
		std::string_view t;
		int line = 1;
		if (scan_.next(t, line))
			fail(line, "count mismatch: extra data " + quoted(t) + " after the " + std::to_string(bal.num_cameras) +
						   " cameras and " + std::to_string(bal.num_points) + " points declared by the header");
		return bal;
	}

   private:
	/** The header line: the camera and point counts into `bal`; returns the observation count. */
	int parse_header(BalProblem& bal)
	{
		std::vector<std::string_view> tok;
		int line = 1;
		if (!scan_.next_line(tok, line)) fail(1, "empty file: expected the header 'num_cameras num_points num_observations'");
		if (tok.size() != 3)
			fail(line, "header must have 3 integers 'num_cameras num_points num_observations', found " +
						   std::to_string(tok.size()) + " values");
		bal.num_cameras = parse_count(tok[0], line, "num_cameras");
		bal.num_points = parse_count(tok[1], line, "num_points");
		return parse_count(tok[2], line, "num_observations");
	}

	/** The `num_obs` observation lines 'camera point x y'. */
	void parse_observations(int num_obs, BalProblem& bal)
	{
		// The header's counts do not size allocations: a 20-byte file can declare 10^9 observations.
		// Storage grows with the data actually read, reserved up to what the text can hold (an
		// observation line takes at least 8 bytes, a parameter 2), so memory stays proportional to the input.
		bal.observations.reserve(std::min(static_cast<size_t>(num_obs), text_size_ / 8));
		std::vector<std::string_view> tok;
		int line = 1;
		for (int k = 0; k < num_obs; k++)
		{
			if (!scan_.next_line(tok, line))
				fail(scan_.line(), "truncated file: the header declares " + std::to_string(num_obs) +
									   " observations, found only " + std::to_string(k));
			if (tok.size() != 4)
				fail(line, "expected observation " + std::to_string(k + 1) + " of " + std::to_string(num_obs) +
							   " as 'camera point x y', found " + std::to_string(tok.size()) +
							   " values (count mismatch with the header?)");
			BalObservation& o = bal.observations.emplace_back();
			o.camera = parse_index(tok[0], line, "camera", bal.num_cameras);
			o.point = parse_index(tok[1], line, "point", bal.num_points);
			o.x = parse_number(tok[2], line);
			o.y = parse_number(tok[3], line);
		}
	}

	/** The camera parameters, then the point coordinates, one number per token on any line. */
	void parse_parameters(BalProblem& bal)
	{
		const size_t num_cam_values = BalProblem::kCameraParams * static_cast<size_t>(bal.num_cameras);
		const size_t num_point_values = BalProblem::kPointParams * static_cast<size_t>(bal.num_points);
		bal.cameras.reserve(std::min(num_cam_values, text_size_ / 2));
		bal.points.reserve(std::min(num_point_values, text_size_ / 2));
		const size_t total = num_cam_values + num_point_values;
		std::string_view t;
		int line = 1;
		for (size_t i = 0; i < total; i++)
		{
			if (!scan_.next(t, line))
				fail(scan_.line(), "truncated file: expected " + std::to_string(total) +
									   " camera and point parameters after the observations, found only " +
									   std::to_string(i) + " (missing " + missing_parameter(i, num_cam_values) + ")");
			const double v = parse_number(t, line);
			if (i < num_cam_values)
				bal.cameras.push_back(v);
			else
				bal.points.push_back(v);
		}
	}

	/** Which parameter the i-th value is: "camera C parameter P" or "point J coordinate K". */
	static std::string missing_parameter(size_t i, size_t num_cam_values)
	{
		if (i < num_cam_values)
			return "camera " + std::to_string(i / BalProblem::kCameraParams) + " parameter " +
				   std::to_string(i % BalProblem::kCameraParams);
		const size_t j = i - num_cam_values;
		return "point " + std::to_string(j / BalProblem::kPointParams) + " coordinate " +
			   std::to_string(j % BalProblem::kPointParams);
	}

	[[noreturn]] void fail(int line, const std::string& reason) const { throw BalParseError(source_, line, reason); }

	/** std::from_chars over the whole token, a leading '+' allowed: the error code (std::errc::invalid_argument
	 * also when characters are left over). */
	template <class T>
	static std::errc from_token(std::string_view t, T& v)
	{
		const char* b = t.data();
		const char* e = b + t.size();
		if (b != e && *b == '+') b++;
		const auto [ptr, ec] = std::from_chars(b, e, v);
		return ec == std::errc() && ptr != e ? std::errc::invalid_argument : ec;
	}
	long parse_integer(std::string_view t, int line, const char* what) const
	{
		long v = 0;
		if (from_token(t, v) != std::errc()) fail(line, std::string("expected an integer ") + what + ", found " + quoted(t));
		return v;
	}
	/** The largest count the header may declare (cameras, points, observations each): 10^9. */
	static constexpr long kMaxCount = 1000000000L;
	int parse_count(std::string_view t, int line, const char* what) const
	{
		const long v = parse_integer(t, line, what);
		if (v <= 0) fail(line, std::string(what) + " must be positive, found " + quoted(t));
		if (v > kMaxCount)
			fail(line, std::string(what) + " must be at most " + std::to_string(kMaxCount) + " (swba's limit), found " +
						   quoted(t));
		return static_cast<int>(v);
	}
	int parse_index(std::string_view t, int line, const char* what, int count) const
	{
		const long v = parse_integer(t, line, (std::string(what) + " index").c_str());
		if (v < 0 || v >= count)
			fail(line, std::string(what) + " index " + std::to_string(v) + " out of range [0, " + std::to_string(count) +
						   ")");
		return static_cast<int>(v);
	}
	double parse_number(std::string_view t, int line) const
	{
		double v = 0;
		const std::errc ec = from_token(t, v);
		if (ec == std::errc::result_out_of_range) fail(line, "number out of the range of double: " + quoted(t));
		if (ec != std::errc()) fail(line, "expected a number, found " + quoted(t));
		if (!std::isfinite(v)) fail(line, "non-finite number " + quoted(t));
		return v;
	}

	Scanner scan_;
	std::string source_;
	size_t text_size_;
};

#ifdef SWBA_HAVE_BZIP2
std::string bunzip2(const std::string& compressed, const std::string& path)
{
	bz_stream s{};
	if (BZ2_bzDecompressInit(&s, 0, 0) != BZ_OK) throw std::runtime_error(path + ": bzip2 initialisation failed");
	std::string out;
	char buf[1 << 16];
	s.next_in = const_cast<char*>(compressed.data());
	s.avail_in = static_cast<unsigned>(compressed.size());
	int rc = BZ_OK;
	while (rc == BZ_OK)
	{
		s.next_out = buf;
		s.avail_out = sizeof(buf);
		rc = BZ2_bzDecompress(&s);
		out.append(buf, sizeof(buf) - s.avail_out);
		if (rc == BZ_OK && s.avail_in == 0 && s.avail_out != 0) break;  // input ended before the stream end
	}
	BZ2_bzDecompressEnd(&s);
	if (rc != BZ_STREAM_END) throw std::runtime_error(path + ": corrupt or truncated bzip2 data");
	return out;
}
#endif
}  // namespace

bool bal_bzip2_supported()
{
#ifdef SWBA_HAVE_BZIP2
	return true;
#else
	return false;
#endif
}

BalProblem parse_bal(const std::string& text, const std::string& source) { return Parser(text, source).parse(); }

BalProblem read_bal(const std::string& path)
{
	std::ifstream f = open_input_file(path, std::ios::binary, "BAL file");
	std::string text((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
	if (f.bad()) throw std::runtime_error(path + ": read error");
	if (text.size() >= 3 && text.compare(0, 3, "BZh") == 0)
	{
#ifdef SWBA_HAVE_BZIP2
		text = bunzip2(text, path);
#else
		throw std::runtime_error(path + ": bzip2-compressed, but this build has no libbz2 support (decompress it "
										"with bunzip2 first)");
#endif
	}
	if (const std::string note = binary_data_note(std::string_view(text)); !note.empty())
		throw std::runtime_error("BAL file '" + path + "': " + note);
	return parse_bal(text, path);
}

void write_bal(const std::string& path, const BalProblem& bal)
{
	write_file_atomically(path, [&](std::ostream& f) {
		char buf[96];
		const auto put = [&](int n) { f.write(buf, std::min<std::streamsize>(n, sizeof(buf) - 1)); };
		put(std::snprintf(buf, sizeof(buf), "%d %d %zu\n", bal.num_cameras, bal.num_points, bal.observations.size()));
		for (const auto& o : bal.observations)
			put(std::snprintf(buf, sizeof(buf), "%d %d %.17g %.17g\n", o.camera, o.point, o.x, o.y));
		for (double v : bal.cameras) put(std::snprintf(buf, sizeof(buf), "%.17g\n", v));
		for (double v : bal.points) put(std::snprintf(buf, sizeof(buf), "%.17g\n", v));
	});
}
}  // namespace swba::io
