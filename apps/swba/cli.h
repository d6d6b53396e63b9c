// Command-line parsing helpers over MRPT's TCLAP: --help prints usage and exits 0,
// a parse error prints a one-line reason and exits 2.
#pragma once

#include <mrpt/3rdparty/tclap/CmdLine.h>

#include <optional>
#include <string>

namespace swba::app
{
/** Parses argv; returns std::nullopt when the command should go on, or the exit code
 * to return (0 after --help/--version, 2 after a parse error). */
std::optional<int> parse_command_line(TCLAP::CmdLine& cmd, int argc, char** argv);

/** Thrown by commands for bad user input; main prints "swba <cmd>: error: <what>" and exits 1. */
struct UsageError : std::runtime_error
{
	using std::runtime_error::runtime_error;
};
}  // namespace swba::app
