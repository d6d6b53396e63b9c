/** \file names.h
 * One enum <-> string mechanism for every option enum: each enum has one table of (value, name)
 * rows, found by argument-dependent lookup, and every parser, printer, help text and error message
 * reads that table — so a name is spelled once ("fixed", never "fix" elsewhere).
 *
 * \code
 *   enum class Color { Red, Green };
 *   constexpr std::array<swba::EnumName<Color>, 2> enum_names(Color)  // next to the enum
 *   { return {{{Color::Red, "red"}, {Color::Green, "green"}}}; }
 *
 *   swba::enum_name(Color::Red);                  // "red"
 *   swba::parse_enum<Color>("green", "color");    // Color::Green
 *   swba::parse_enum<Color>("blue", "color");     // std::invalid_argument:
 *                                                 //   "unknown color 'blue' (expected red or green)"
 * \endcode */
#pragma once

#include <array>
#include <stdexcept>
#include <string>
#include <string_view>

namespace swba
{
/** One row of an enum's name table. The first row of a value gives its name; further rows of the
 * same value are accepted spellings (aliases), not listed as choices. */
template <class E>
struct EnumName
{
	E value;
	const char* name;
	bool alias = false;
};

/** The table of E: `enum_names(E{})`, declared next to the enum (found by argument-dependent lookup). */
template <class E>
constexpr auto enum_table()
{
	return enum_names(E{});
}

/** The name of `value`; throws std::logic_error if the table lacks it (a programming error). */
template <class E>
std::string enum_name(E value)
{
	for (const auto& row : enum_table<E>())
		if (row.value == value) return row.name;
	throw std::logic_error("enum value without a name");
}

/** The valid names in table order, joined by `separator` (aliases left out), for help texts. */
template <class E>
std::string enum_choices(std::string_view separator = ", ")
{
	std::string out;
	for (const auto& row : enum_table<E>())
	{
		if (row.alias) continue;
		if (!out.empty()) out += separator;
		out += row.name;
	}
	return out;
}

/** The valid names as a sentence: "a", "a or b", "a, b or c" (for error messages). */
template <class E>
std::string enum_choices_sentence()
{
	std::string out, last;
	for (const auto& row : enum_table<E>())
	{
		if (row.alias) continue;
		if (!last.empty()) out += (out.empty() ? "" : ", ") + last;
		last = row.name;
	}
	return out.empty() ? last : out + " or " + last;
}

/** The value named `text` (exact match; aliases accepted). Throws std::invalid_argument
 * "unknown <what> '<text>' (expected a, b or c)" otherwise. */
template <class E>
E parse_enum(std::string_view text, std::string_view what)
{
	for (const auto& row : enum_table<E>())
		if (text == row.name) return row.value;
	throw std::invalid_argument("unknown " + std::string(what) + " '" + std::string(text) + "' (expected " +
								enum_choices_sentence<E>() + ")");
}
}  // namespace swba
