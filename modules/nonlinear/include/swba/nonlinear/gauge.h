/** \file gauge.h
 * Gauge handling modes of a problem whose cost is invariant under a global motion, shared by the
 * estimators (sliding window, mono BA). */
#pragma once

#include <swba/core/names.h>

#include <array>
#include <string>

namespace swba
{
/** How an estimator removes or damps the gauge freedom of its problem. */
enum class GaugeMode
{
	Free,   ///< nothing fixed: LM damping copes with the null space
	Fixed,  ///< chosen poses are constant
	Prior   ///< an SE(3) PosePriorFactor with information W·I on the chosen poses
};

constexpr std::array<EnumName<GaugeMode>, 3> enum_names(GaugeMode)
{
	return {{{GaugeMode::Free, "free"}, {GaugeMode::Fixed, "fixed"}, {GaugeMode::Prior, "prior"}}};
}

/** Parses "free", "fixed", "prior"; throws std::invalid_argument otherwise. */
GaugeMode parse_gauge_mode(const std::string& name);
std::string to_string(GaugeMode mode);
}  // namespace swba
