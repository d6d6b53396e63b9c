// Harness: TUM trajectories (swba::eval::read_tum, the stream entry point).
#include "fuzz_common.h"

#include <swba/eval/trajectory.h>

#include <exception>
#include <sstream>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
	std::istringstream in(swba::fuzz::as_text(data, size));
	try
	{
		(void)swba::eval::read_tum(in, "<fuzz>");
	}
	catch (const std::exception& e)
	{
		swba::fuzz::rejected(e);
	}
	return 0;
}
