#include <swba/nonlinear/gauge.h>

#include <stdexcept>

namespace swba
{
GaugeMode parse_gauge_mode(const std::string& name)
{
	if (name == "free") return GaugeMode::Free;
	if (name == "fixed") return GaugeMode::Fixed;
	if (name == "prior") return GaugeMode::Prior;
	throw std::invalid_argument("unknown gauge '" + name + "' (expected free, fixed or prior)");
}

std::string to_string(GaugeMode mode)
{
	switch (mode)
	{
		case GaugeMode::Free: return "free";
		case GaugeMode::Fixed: return "fixed";
		case GaugeMode::Prior: return "prior";
	}
	return "?";
}
}  // namespace swba
