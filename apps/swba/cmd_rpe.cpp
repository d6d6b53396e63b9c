// swba rpe: relative pose error as evo_rpe (the shared implementation is in cmd_ape.cpp).
#include "cli.h"
#include "command.h"

namespace swba::app
{
int run_trajectory_metric_command(bool relative, int argc, char** argv);

namespace
{
int run_rpe(int argc, char** argv) { return run_trajectory_metric_command(true, argc, argv); }
SWBA_REGISTER_COMMAND("rpe", "relative pose error of a trajectory vs a reference (as evo_rpe)", run_rpe);
}  // namespace
}  // namespace swba::app
