// Harness: MRPT rawlogs (swba::io::read_rawlog takes a path: the input goes through a scratch file).
// Each input is read twice: with the defaults (damage is an error, landmark IDs required) and with
// allow_truncated + no ID requirement, which keeps the steps read before damage and reaches the
// reading-validation code with whatever the corrupt objects hold.
#include "fuzz_common.h"

#include <swba/io/rawlog.h>


extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
	const std::string path = swba::fuzz::write_scratch_file("input.rawlog", swba::fuzz::as_text(data, size));
	swba::io::RawlogReaderOptions lenient;
	lenient.allow_truncated = true;
	lenient.require_landmark_ids = false;
	for (const auto& options : {swba::io::RawlogReaderOptions{}, lenient})
	{
		swba::fuzz::read_or_reject([&] { (void)swba::io::read_rawlog(path, options); });
	}
	return 0;
}
