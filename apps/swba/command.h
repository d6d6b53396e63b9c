// The swba program's subcommands: each cmd_*.cpp registers itself with SWBA_REGISTER_COMMAND.
#pragma once

#include <functional>
#include <map>
#include <string>

namespace swba::app
{
/** A subcommand: `run(argc, argv)` receives argv[0] = "swba <name>"; returns the exit code. */
struct Command
{
	std::string name;
	std::string summary;
	std::function<int(int, char**)> run;
};

/** All registered subcommands, sorted by name. */
std::map<std::string, Command>& command_registry();

struct CommandRegistrar
{
	CommandRegistrar(std::string name, std::string summary, std::function<int(int, char**)> run)
	{
		auto& reg = command_registry();
		reg[name] = Command{name, std::move(summary), std::move(run)};
	}
};
}  // namespace swba::app

#define SWBA_CONCAT_INNER(a, b) a##b
#define SWBA_CONCAT(a, b) SWBA_CONCAT_INNER(a, b)
/** Registers `fn` (int(int, char**)) as subcommand `name`. */
#define SWBA_REGISTER_COMMAND(name, summary, fn) \
	static const ::swba::app::CommandRegistrar SWBA_CONCAT(swba_cmd_registrar_, __LINE__)(name, summary, fn)
