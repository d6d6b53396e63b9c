// Harness: the INI configuration of `swba run` (swba::apps::load_run_config_text).
#include "fuzz_common.h"

#include <swba/apps/run_options.h>


extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
	swba::apps::RunOptions options;
	swba::fuzz::read_or_reject(
		[&]
		{
			swba::apps::load_run_config_text(swba::fuzz::as_text(data, size), "<fuzz>", options);
			(void)swba::apps::format_run_config(options);
		});
	return 0;
}
