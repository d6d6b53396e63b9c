/** \file file.h
 * Input files: every reader checks its path with check_input_file before opening it, so that a
 * directory, a FIFO or a device (/dev/zero, /dev/stdin) is refused with one line instead of being
 * read forever or handed to a parser. */
#pragma once

#include <fstream>
#include <string>

namespace swba
{
/** Throws std::runtime_error "<path>: <what>" unless `path` names an existing regular file (symbolic
 * links followed): "file does not exist", "is a directory, not a file", "is not a regular file (a FIFO,
 * device or socket)". `what_file` (e.g. "rawlog") prefixes the message when not empty. */
void check_input_file(const std::string& path, const std::string& what_file = "");

/** check_input_file, then an open std::ifstream (throws "<path>: cannot open: <OS reason>"). */
std::ifstream open_input_file(const std::string& path, std::ios::openmode mode = std::ios::in,
							  const std::string& what_file = "");
}  // namespace swba
