// swba: sliding-window bundle adjustment and graph-SLAM back end on MRPT.
#include <algorithm>
#include <cstring>
#include <exception>
#include <iostream>
#include <string>

#include <swba/io/rawlog.h>
#include <swba/linear/rank_update.h>

#include "cli.h"
#include "command.h"

namespace swba::app
{
std::map<std::string, Command>& command_registry()
{
	static std::map<std::string, Command> registry;
	return registry;
}

static void print_usage(std::ostream& os)
{
	os << "swba — sliding-window bundle adjustment and graph-SLAM back end on MRPT\n\n"
		  "Usage: swba <command> [options]     (swba <command> --help for details)\n\nCommands:\n";
	std::size_t width = 0;  // the summaries in one column after the longest name
	for (const auto& [name, c] : command_registry()) width = std::max(width, name.size());
	for (const auto& [name, c] : command_registry())
		os << "  " << name << std::string(width + 2 - name.size(), ' ') << c.summary << "\n";
}
}  // namespace swba::app

int main(int argc, char** argv)
{
	using namespace swba::app;
	const bool help = argc >= 2 && (!std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h") ||
									 !std::strcmp(argv[1], "help"));
	if (argc < 2 || (help && argc == 2))
	{
		print_usage(argc < 2 ? std::cerr : std::cout);
		return argc < 2 ? 2 : 0;
	}
	// "swba help <command>" = "swba <command> --help"; "swba --version" = "swba version".
	const std::string name = help ? argv[2] : !std::strcmp(argv[1], "--version") ? "version" : argv[1];
	auto& reg = command_registry();
	auto it = reg.find(name);
	if (it == reg.end())
	{
		std::cerr << "swba: error: unknown command '" << name << "' (see swba --help)\n";
		return 2;
	}
	// argv[0] becomes "swba <name>" so that usage messages name the subcommand.
	std::string prog = "swba " + name;
	std::vector<char*> args;
	args.push_back(prog.data());
	std::string help_flag = "--help";
	if (help)
		args.push_back(help_flag.data());
	else
		for (int i = 2; i < argc; i++) args.push_back(argv[i]);
	try
	{
		if (!help) swba::active_simd_level();  // a bad SWBA_SIMD fails here, not in the middle of a run
		return it->second.run(static_cast<int>(args.size()), args.data());
	}
	catch (const UsageError& e)
	{
		std::cerr << prog << ": error: " << swba::io::mrpt_exception_summary(e.what(), swba::io::locale_is_utf8())
				  << " (see --help)\n";
		return 2;
	}
	catch (const std::exception& e)
	{
		// One line, printable: an MRPT exception carries a call stack with addresses, and a message may
		// quote bytes read from a file.
		std::cerr << prog << ": error: " << swba::io::mrpt_exception_summary(e.what(), swba::io::locale_is_utf8())
				  << "\n";
		return 1;
	}
}
