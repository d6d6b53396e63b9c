// swba version: prints the program and dependency versions, and the SIMD level of the rank-update
// kernel this machine runs (swba/linear/rank_update.h).
#include <iostream>

#include "cli.h"
#include "command.h"

namespace
{
int run_version(int argc, char** argv)
{
	TCLAP::CmdLine cmd("Prints the versions of swba and of the libraries it was built with.", ' ', "0.1.0");
	if (auto rc = swba::app::parse_command_line(cmd, argc, argv)) return *rc;
	std::cout << swba::app::version_line() << "\n";
	return 0;
}
SWBA_REGISTER_COMMAND("version", "print versions", run_version);
}  // namespace
