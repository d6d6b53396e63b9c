#include <swba/eval/text_format.h>

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

std::string csv_field(const std::string& s)
{
	if (s.find_first_of(",\"\n") == std::string::npos) return s;
	std::string out = "\"";
	for (char c : s) out += (c == '"') ? std::string("\"\"") : std::string(1, c);
	return out + "\"";
}
}  // namespace swba::eval
