// Harness: the INI configuration of `swba run` (swba::apps::load_run_config_text).
#include "fuzz_common.h"

#include <swba/apps/run_options.h>

#include <exception>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
	swba::apps::RunOptions options;
	try
	{
		swba::apps::load_run_config_text(swba::fuzz::as_text(data, size), "<fuzz>", options);
		(void)swba::apps::format_run_config(options);
	}
	catch (const std::exception& e)
	{
		swba::fuzz::rejected(e);
	}
	return 0;
}
