// JSON values of the files the applications write (summary.json: run/report.cpp; sweep.json:
// sweep/plan.cpp), where a field that does not apply is null. Internal to the applications.
#pragma once

#include <nlohmann/json.hpp>

#include <string>

namespace swba::apps
{
/** A string, or null when it is empty (a field that does not apply). */
inline nlohmann::ordered_json string_or_null(const std::string& s)
{
	return s.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(s);
}

/** A whole number whose 0 means "none" (a window W, a seed), or null for 0. */
template <class Int>
nlohmann::ordered_json nonzero_or_null(Int n)
{
	return n ? nlohmann::ordered_json(n) : nlohmann::ordered_json(nullptr);
}
}  // namespace swba::apps
