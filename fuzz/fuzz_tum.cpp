// Harness: TUM trajectories (swba::eval::read_tum, the stream entry point).
#include "fuzz_common.h"

#include <swba/eval/trajectory.h>

#include <sstream>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
	std::istringstream in(swba::fuzz::as_text(data, size));
	swba::fuzz::read_or_reject([&] { (void)swba::eval::read_tum(in, "<fuzz>"); });
	return 0;
}
