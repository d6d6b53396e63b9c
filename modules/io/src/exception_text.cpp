// One printable line from an exception's text (MRPT's multi-line exceptions included).
#include <swba/io/rawlog.h>

#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>

namespace swba::io
{
namespace
{
/** Length of the well-formed UTF-8 character of two to four bytes at s[i] (RFC 3629: no overlong
 * form, no surrogate, nothing above U+10FFFF), or 0. */
std::size_t utf8_length(const std::string& s, std::size_t i)
{
	const auto b = [&](std::size_t k) { return static_cast<unsigned char>(s[i + k]); };
	const unsigned char c = b(0);
	const std::size_t n = c >= 0xc2 && c <= 0xdf ? 2 : c >= 0xe0 && c <= 0xef ? 3 : c >= 0xf0 && c <= 0xf4 ? 4 : 0;
	if (n == 0 || i + n > s.size()) return 0;
	for (std::size_t k = 1; k < n; k++)
		if ((b(k) & 0xc0) != 0x80) return 0;
	if ((c == 0xe0 && b(1) < 0xa0) || (c == 0xed && b(1) > 0x9f) || (c == 0xf0 && b(1) < 0x90) ||
		(c == 0xf4 && b(1) > 0x8f))
		return 0;
	return n;
}
}  // namespace

bool locale_is_utf8()
{
	for (const char* var : {"LC_ALL", "LC_CTYPE", "LANG"})
	{
		const char* v = std::getenv(var);
		if (!v || !*v) continue;
		std::string s(v);
		for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
		return s.find("utf-8") != std::string::npos || s.find("utf8") != std::string::npos;
	}
	return false;
}

std::string mrpt_exception_summary(const std::string& what, bool keep_utf8)
{
	std::istringstream in(what);
	std::string line, message, location, first;
	while (std::getline(in, line))
	{
		const auto b = line.find_first_not_of(" \t\r");
		if (b == std::string::npos) continue;
		const auto e = line.find_last_not_of(" \t\r");
		line = line.substr(b, e - b + 1);
		if (line.rfind("Message:", 0) == 0 && message.empty())
		{
			const auto m = line.find_first_not_of(" \t", 8);
			message = m == std::string::npos ? "" : line.substr(m);
		}
		else if (line.rfind("Location:", 0) == 0 && location.empty())
		{
			// "Location: ./libs/.../File.cpp:721: [function…" → "File.cpp:721"
			std::string loc = line.substr(9);
			const auto colon2 = loc.find(": ");
			if (colon2 != std::string::npos) loc = loc.substr(0, colon2);
			const auto slash = loc.find_last_of('/');
			if (slash != std::string::npos) loc = loc.substr(slash + 1);
			const auto lb = loc.find_first_not_of(' ');
			location = lb == std::string::npos ? "" : loc.substr(lb);
		}
		else if (first.empty() && line.rfind("====", 0) != 0)
			first = line;
	}
	std::string summary = first.empty() ? what : first;
	if (!message.empty()) summary = location.empty() ? message : message + " (" + location + ")";
	// MRPT quotes what it read (a class name from a corrupt file): never print raw bytes.
	std::string out;
	for (std::size_t i = 0; i < summary.size(); i++)
	{
		const unsigned char c = static_cast<unsigned char>(summary[i]);
		const std::size_t n = keep_utf8 ? utf8_length(summary, i) : 0;
		if (c >= 0x20 && c < 0x7f)
			out += static_cast<char>(c);
		else if (n > 0)
		{
			out += summary.substr(i, n);
			i += n - 1;
		}
		else
		{
			char esc[5];
			std::snprintf(esc, sizeof(esc), "\\x%02x", c);
			out += esc;
		}
	}
	return out;
}
}  // namespace swba::io
