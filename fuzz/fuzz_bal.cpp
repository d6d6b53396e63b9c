// Harness: BAL problems. Text goes to swba::io::parse_bal directly; input starting with the bzip2
// magic "BZh" goes through a scratch file and read_bal, which decompresses it (when libbz2 is linked).
#include "fuzz_common.h"

#include <swba/io/bal.h>


extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
	const std::string bytes = swba::fuzz::as_text(data, size);
	swba::fuzz::read_or_reject(
		[&]
		{
			if (bytes.compare(0, 3, "BZh") == 0)
				(void)swba::io::read_bal(swba::fuzz::write_scratch_file("input.bal", bytes));
			else
				(void)swba::io::parse_bal(bytes, "<fuzz>");
		});
	return 0;
}
