// Command-line parsing helpers over MRPT's TCLAP: --help prints usage and exits 0,
// a parse error prints a one-line reason and exits 2.
#pragma once

#include <mrpt/3rdparty/tclap/CmdLine.h>

#include <functional>
#include <iostream>
#include <optional>
#include <stdexcept>
#include <string>

namespace swba::app
{
/** Parses argv; returns std::nullopt when the command should go on, or the exit code
 * to return (0 after --help/--version, 2 after a parse error). An argument no positional takes is
 * named ("unexpected argument 'x'"), followed by `extra_argument_hint` when given. */
std::optional<int> parse_command_line(TCLAP::CmdLine& cmd, int argc, char** argv,
									  const std::string& extra_argument_hint = "");

/** swba's data directory (config/, rawlogs/, data/): <prefix>/share/swba for an installed swba (found
 * from the executable's own path), else the source tree's share/. */
std::string share_dir();

/** "swba 0.1.0 (MRPT …, Eigen …; rank-update kernel …)": what `swba version` and every command's
 * --version print. */
std::string version_line();

/** This swba executable's absolute path (from /proc/self/exe; "swba" when it cannot be read): what
 * generated job lines call. */
std::string this_executable();

/** An optional `--<flag> VALUE` that overrides a value the command's options already hold (an INI's, or
 * the options' own default, which `default_text` names: the description ends "(Default: <default_text>)").
 * Read only when isSet(): it has no default of its own. */
template <class T>
struct OverrideArg : TCLAP::ValueArg<T>
{
	OverrideArg(const std::string& flag, const std::string& type_description, const std::string& default_text,
				const std::string& description, TCLAP::CmdLineInterface& cmd)
		: TCLAP::ValueArg<T>("", flag, description + " (Default: " + default_text + ")", false, T{}, type_description,
							 cmd)
	{
	}
};

/** `--threads N` of the solver commands: "threads for evaluation and assembly (Default: 1)". */
inline TCLAP::ValueArg<int> threads_arg(TCLAP::CmdLine& cmd)
{
	return TCLAP::ValueArg<int>("", "threads", "threads for evaluation and assembly (Default: 1)", false, 1, "N", cmd);
}

/** `--<flag> K`: "maximum LM iterations (Default: <default_value>)". */
inline TCLAP::ValueArg<int> max_iterations_arg(TCLAP::CmdLine& cmd, int default_value,
											   const std::string& flag = "max-iterations")
{
	return TCLAP::ValueArg<int>("", flag, "maximum LM iterations (Default: " + std::to_string(default_value) + ")",
								false, default_value, "K", cmd);
}

/** `-q/--quiet` of the solver commands: "do not print the per-iteration table". */
inline TCLAP::SwitchArg quiet_arg(TCLAP::CmdLine& cmd)
{
	return TCLAP::SwitchArg("q", "quiet", "do not print the per-iteration table", cmd);
}

/** A subcommand over a command-line struct `Args` (its TCLAP arguments and `cmd`, their CmdLine):
 * parses argv into a fresh Args (parse_command_line's exit code, when it gives one), then returns
 * run(args). */
template <class Args, class Run>
std::function<int(int, char**)> parsed_command(Run run)
{
	return [run](int argc, char** argv) {
		Args args;
		if (auto rc = parse_command_line(args.cmd, argc, argv)) return *rc;
		return run(args);
	};
}

/** The subcommand that runs app(options_from(args), std::cout, std::cerr) and exits 0 (options_from:
 * the function declared next to `Args` that makes the app's options, throwing UsageError). */
template <class Args, class App>
std::function<int(int, char**)> app_command(App app)
{
	return parsed_command<Args>([app](Args& args) {
		app(options_from(args), std::cout, std::cerr);
		return 0;
	});
}

/** Thrown by commands for a bad command line (an option's value out of range, a missing or superfluous
 * argument, options that exclude each other); main prints "swba <cmd>: error: <what> (see --help)" and
 * exits 2, as for TCLAP's own parse errors. A bad input file or a failure while running is any other
 * exception: exit 1. */
struct UsageError : std::runtime_error
{
	using std::runtime_error::runtime_error;
};

/** options.validate(), its std::invalid_argument turned into a UsageError with the same message. */
template <class Options>
void validate_usage(const Options& options)
{
	try
	{
		options.validate();
	}
	catch (const std::invalid_argument& e)
	{
		throw UsageError(e.what());
	}
}
}  // namespace swba::app
