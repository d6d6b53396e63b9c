/** \file file.h
 * Files in and out. Every reader checks its path with check_input_file before opening it, so that a
 * directory, a FIFO or a device (/dev/zero, /dev/stdin) is refused with one line instead of being
 * read forever or handed to a parser. Every writer goes through write_file_atomically, so that a
 * file is either complete or not there, and a failure names the file and the OS reason. */
#pragma once

#include <fstream>
#include <functional>
#include <ostream>
#include <string>
#include <string_view>

namespace swba
{
/** Throws std::runtime_error "<path>: <what>" unless `path` names an existing regular file (symbolic
 * links followed): "file does not exist", "is a directory, not a file", "is not a regular file (a FIFO,
 * device or socket)". `what_file` (e.g. "rawlog") prefixes the message when not empty. */
void check_input_file(const std::string& path, const std::string& what_file = "");

/** check_input_file, then an open std::ifstream (throws "<path>: cannot open: <OS reason>"). */
std::ifstream open_input_file(const std::string& path, std::ios::openmode mode = std::ios::in,
							  const std::string& what_file = "");

/** The whole contents of a text file (open_input_file's checks first). Throws std::runtime_error
 * "<what_file> '<path>': not a text file (a NUL byte at byte N: binary data, e.g. a rawlog)" when
 * it holds a NUL byte, so that a binary file given where text is expected is named, never parsed. */
std::string read_text_file(const std::string& path, const std::string& what_file = "");

/** For readers that stream a text file: "not a text file (a NUL byte at byte N: binary data, e.g. a rawlog)"
 * when the first 64 KiB of `in` hold a NUL byte, else ""; `in` is rewound to its start either way. */
std::string binary_data_note(std::istream& in);
/** The same test on the first 64 KiB of `text`, for readers that hold the file in memory. */
std::string binary_data_note(std::string_view text);

/** Writes `path` through `write`: into "<path>.tmp.<pid>" in the same directory, flushed and closed,
 * then renamed over `path`, so that a reader (or a run interrupted mid-write) never leaves a
 * half-written file, and an existing `path` stays intact when the write fails. A `path` that exists
 * and is no regular file (a device, a FIFO) is written in place. Throws
 * std::runtime_error "cannot write '<path>': <OS reason>" (the temporary file removed); an exception
 * thrown by `write` propagates after the temporary file is removed. */
void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& write,
						   std::ios::openmode mode = std::ios::out);
/** write_file_atomically of `text` as it is. */
void write_text_file_atomically(const std::string& path, const std::string& text);

/** Creates directory `dir` and its parents if missing; throws std::runtime_error "cannot create
 * <what> '<dir>'[: <OS reason>]" unless `dir` is then a directory (e.g. what = "output directory"). */
void create_directory_or_throw(const std::string& dir, const std::string& what);
}  // namespace swba
