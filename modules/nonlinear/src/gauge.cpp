#include <swba/nonlinear/gauge.h>

namespace swba
{
GaugeMode parse_gauge_mode(const std::string& name) { return parse_enum<GaugeMode>(name, "gauge"); }

std::string to_string(GaugeMode mode) { return enum_name(mode); }
}  // namespace swba
