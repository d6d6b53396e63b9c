// Internal to modules/problems: the names of option enums, one table per enum, so that parsing,
// printing and the list in the error message come from the same place.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>

namespace swba::problems::detail
{
template <typename E>
struct EnumName
{
	E value;
	const char* name;
};

/** The value called `name` in `table`; otherwise throws std::invalid_argument
 * "unknown <what> '<name>' (expected a, b or c)", the names listed in table order. */
template <typename E, std::size_t N>
E parse_enum(const std::string& name, const EnumName<E> (&table)[N], const char* what)
{
	for (const auto& entry : table)
		if (name == entry.name) return entry.value;
	std::string expected;
	for (std::size_t i = 0; i < N; i++) expected += (i == 0 ? "" : i + 1 == N ? " or " : ", ") + std::string(table[i].name);
	throw std::invalid_argument("unknown " + std::string(what) + " '" + name + "' (expected " + expected + ")");
}

/** The name of `value` in `table`, "?" if it has none. */
template <typename E, std::size_t N>
std::string enum_name(E value, const EnumName<E> (&table)[N])
{
	for (const auto& entry : table)
		if (entry.value == value) return entry.name;
	return "?";
}
}  // namespace swba::problems::detail
