/** \file text_format.h
 * Number and field formatting shared by the text, CSV, JSON, TUM and gnuplot writers. */
#pragma once

#include <string>

namespace swba::eval
{
/** `v` with `digits` significant digits in printf's %g style (17 round-trips a double exactly). */
std::string format_significant(double v, int digits);
/** `v` formatted by one printf conversion for a double, e.g. "%.2f" (a table cell). */
std::string format_printf(const char* format, double v);
/** Append `v` to `out` exactly as printf's "%.<precision>f" (append_fixed) or "%.<precision>e"
 * (append_scientific) writes it — the same correctly rounded digits, "inf", "nan", "-0.0…" — through
 * std::to_chars, without printf's format parsing: the writers of long files (trajectories, covariances)
 * call them hundreds of thousands of times a run. */
void append_fixed(std::string& out, double v, int precision);
void append_scientific(std::string& out, double v, int precision);
/** A CSV field: quoted (with doubled quotes) when it holds a comma, a quote or a newline. */
std::string csv_field(const std::string& s);
}  // namespace swba::eval
