/** \file timing.h
 * Wall-clock durations for the solver summaries, the estimators' step timings and the apps' reports:
 * the steady clock (monotonic, unaffected by clock adjustments), read in seconds as a double. */
#pragma once

#include <chrono>

namespace swba
{
using SteadyClock = std::chrono::steady_clock;

/** Seconds elapsed on the steady clock since `t0`. */
inline double seconds_since(SteadyClock::time_point t0)
{
	return std::chrono::duration<double>(SteadyClock::now() - t0).count();
}
}  // namespace swba
