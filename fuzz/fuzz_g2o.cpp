// Harness: g2o pose graphs (swba::io::read_g2o, stream entry point). Every input is read under both
// information policies: Repair reaches the eigen-decomposition that Strict stops before.
#include "fuzz_common.h"

#include <swba/io/g2o.h>

#include <sstream>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
	const std::string text = swba::fuzz::as_text(data, size);
	for (const auto policy : {swba::io::InformationPolicy::Strict, swba::io::InformationPolicy::Repair})
	{
		swba::io::G2oReadOptions options;
		options.information = policy;
		std::istringstream in(text);
		swba::fuzz::read_or_reject(
			[&]
			{
				const auto graph = swba::io::read_g2o(in, "<fuzz>", options);
				(void)graph.skipped_summary();
				(void)graph.repaired_information.summary(graph.num_edges(), options.relative_floor);
			});
	}
	return 0;
}
