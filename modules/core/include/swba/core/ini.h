/** \file ini.h
 * INI keys of an options struct, declared next to the struct: one row per key with its section,
 * unit and meaning, and how the value is read from and written to text. An application composes
 * the keys of the options it holds (append_keys) and loads a file over them (swba/apps/run_options.h
 * rejects unknown sections and keys). Values are in the INI's units (degrees where the key says so);
 * the struct's fields keep the library's (radians).
 *
 * \code
 *   IniKeys<SolverOptions> keys = SolverOptions::ini_keys("solver");
 *   IniKeys<MyAppOptions> all;
 *   append_keys(all, keys, [](auto& o) -> auto& { return o.solver; });
 * \endcode */
#pragma once

#include <swba/core/names.h>

#include <functional>
#include <string>
#include <vector>

namespace swba
{
template <class T>
struct IniKey
{
	std::string section, key, unit, meaning;
	/** Parses the text (throws std::invalid_argument with the reason) and stores the value. */
	std::function<void(const std::string&, T&)> set;
	/** The value as the INI writes it (reads back to the same value). */
	std::function<std::string(const T&)> get;
};
template <class T>
using IniKeys = std::vector<IniKey<T>>;

/** Appends the keys of a member options struct to those of its owner. `member(owner)` returns the
 * member by reference, for a const and a non-const owner (a generic lambda `[](auto& o) -> auto&`). */
template <class T, class Sub, class Member>
void append_keys(IniKeys<T>& out, const IniKeys<Sub>& keys, Member member)
{
	for (const auto& k : keys)
		out.push_back({k.section, k.key, k.unit, k.meaning,
					   [set = k.set, member](const std::string& v, T& o) { set(v, member(o)); },
					   [get = k.get, member](const T& o) { return get(member(o)); }});
}

/** Value parsers and printers for IniKey::set / get. Each parser reads the whole text or throws
 * std::invalid_argument quoting it ("'10x' is not an integer"). */
namespace ini
{
double parse_double(const std::string& v);  ///< finite
long long parse_integer(const std::string& v);
int parse_int_min(const std::string& v, long long min_value);
bool parse_bool(const std::string& v);  ///< true/false, 1/0, yes/no, on/off (any case)
double parse_positive(const std::string& v);
double parse_non_negative(const std::string& v);
/** The shortest text that reads back to `v` exactly (integers without a decimal point). */
std::string format_double(double v);
std::string format_bool(bool b);

/** A key holding a double member, read with `parse` (e.g. parse_positive) and written exactly. */
template <class T>
IniKey<T> number_key(const std::string& section, const std::string& key, const std::string& unit,
					 const std::string& meaning, double T::*field, double (*parse)(const std::string&))
{
	return {section, key, unit, meaning, [field, parse](const std::string& v, T& o) { o.*field = parse(v); },
			[field](const T& o) { return format_double(o.*field); }};
}

/** A key holding an integer member of at least `min_value` (parse_int_min), written in decimal. */
template <class T, class I>
IniKey<T> int_key(const std::string& section, const std::string& key, const std::string& unit,
				  const std::string& meaning, I T::*field, long long min_value)
{
	return {section, key, unit, meaning,
			[field, min_value](const std::string& v, T& o) { o.*field = static_cast<I>(parse_int_min(v, min_value)); },
			[field](const T& o) { return std::to_string(o.*field); }};
}

/** A key holding a bool member (unit "bool"; parse_bool, format_bool). */
template <class T>
IniKey<T> bool_key(const std::string& section, const std::string& key, const std::string& meaning, bool T::*field)
{
	return {section, key, "bool", meaning, [field](const std::string& v, T& o) { o.*field = parse_bool(v); },
			[field](const T& o) { return format_bool(o.*field); }};
}

/** A key holding a string member taken as written (e.g. a path; empty allowed). */
template <class T>
IniKey<T> text_key(const std::string& section, const std::string& key, const std::string& unit,
				   const std::string& meaning, std::string T::*field)
{
	return {section, key, unit, meaning, [field](const std::string& v, T& o) { o.*field = v; },
			[field](const T& o) { return o.*field; }};
}

/** A key holding an enum with a names table (swba/core/names.h); its unit lists the names and a
 * bad value is reported as "unknown <what> '<text>' (expected …)". */
template <class T, class E, class Member>
IniKey<T> enum_key(const std::string& section, const std::string& key, const std::string& meaning,
				   const std::string& what, Member member)
{
	return {section, key, enum_choices<E>("|"), meaning,
			[member, what](const std::string& v, T& o) { member(o) = parse_enum<E>(v, what); },
			[member](const T& o) { return enum_name(member(o)); }};
}
}  // namespace ini
}  // namespace swba
