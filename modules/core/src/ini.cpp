#include <swba/core/ini.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

namespace swba::ini
{
namespace
{
/** The whole of `v` read by `read` (std::stod or std::stoll's signature), else "'v' is not <what>". */
template <class Read>
auto read_whole(const std::string& v, Read read, const char* what)
{
	std::size_t pos = 0;
	decltype(read(v, &pos)) x{};
	try
	{
		x = read(v, &pos);
	}
	catch (const std::exception&)
	{
		pos = std::string::npos;
	}
	if (pos != v.size()) throw std::invalid_argument("'" + v + "' is not " + what);
	return x;
}
}  // namespace

double parse_double(const std::string& v)
{
	const double d = read_whole(v, [](const std::string& s, std::size_t* pos) { return std::stod(s, pos); }, "a number");
	if (!std::isfinite(d)) throw std::invalid_argument("'" + v + "' is not finite");
	return d;
}

long long parse_integer(const std::string& v)
{
	return read_whole(v, [](const std::string& s, std::size_t* pos) { return std::stoll(s, pos); }, "an integer");
}

int parse_int_min(const std::string& v, long long min_value)
{
	const long long i = parse_integer(v);
	if (i < min_value || i > std::numeric_limits<int>::max())
		throw std::invalid_argument("'" + v + "' must be an integer >= " + std::to_string(min_value));
	return static_cast<int>(i);
}

bool parse_bool(const std::string& v)
{
	std::string l = v;
	std::transform(l.begin(), l.end(), l.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
	if (l == "true" || l == "1" || l == "yes" || l == "on") return true;
	if (l == "false" || l == "0" || l == "no" || l == "off") return false;
	throw std::invalid_argument("'" + v + "' is not a boolean (true/false, 1/0, yes/no, on/off)");
}

double parse_positive(const std::string& v)
{
	const double d = parse_double(v);
	if (!(d > 0)) throw std::invalid_argument("'" + v + "' must be > 0");
	return d;
}

double parse_non_negative(const std::string& v)
{
	const double d = parse_double(v);
	if (d < 0) throw std::invalid_argument("'" + v + "' must be >= 0");
	return d;
}

std::string format_double(double v)
{
	char buf[64];
	if (v == std::floor(v) && std::abs(v) < 1e15)
	{
		std::snprintf(buf, sizeof(buf), "%.0f", v);
		return buf;
	}
	for (int p = 1; p <= 17; p++)
	{
		std::snprintf(buf, sizeof(buf), "%.*g", p, v);
		if (std::stod(buf) == v) return buf;
	}
	return buf;
}

std::string format_bool(bool b) { return b ? "true" : "false"; }
}  // namespace swba::ini
