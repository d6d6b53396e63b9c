#include <swba/eval/text_format.h>

#include <charconv>
#include <cstdio>

namespace swba::eval
{
std::string format_significant(double v, int digits)
{
	char buf[48];
	std::snprintf(buf, sizeof(buf), "%.*g", digits, v);
	return buf;
}

std::string format_printf(const char* format, double v)
{
	char buf[64];
	std::snprintf(buf, sizeof(buf), format, v);
	return buf;
}

namespace
{
void append_to_chars(std::string& out, double v, std::chars_format format, int precision, const char* printf_format)
{
	char buf[128];
	const auto [end, ec] = std::to_chars(buf, buf + sizeof(buf), v, format, precision);
	if (ec == std::errc())
	{
		out.append(buf, end);
		return;
	}
	// Longer than the buffer (a large |v| in fixed notation, or a large precision): printf's own length.
	const int n = std::snprintf(nullptr, 0, printf_format, precision, v);
	std::string s(static_cast<std::size_t>(n) + 1, '\0');
	std::snprintf(s.data(), s.size(), printf_format, precision, v);
	out.append(s.data(), static_cast<std::size_t>(n));
}
}  // namespace

void append_fixed(std::string& out, double v, int precision)
{
	append_to_chars(out, v, std::chars_format::fixed, precision, "%.*f");
}

void append_scientific(std::string& out, double v, int precision)
{
	append_to_chars(out, v, std::chars_format::scientific, precision, "%.*e");
}

std::string csv_field(const std::string& s)
{
	if (s.find_first_of(",\"\n") == std::string::npos) return s;
	std::string out = "\"";
	for (char c : s) out += (c == '"') ? std::string("\"\"") : std::string(1, c);
	return out + "\"";
}
}  // namespace swba::eval
