// Harness: direct-BA data set directories (swba::io::read_directba_dataset reads a directory).
// The input is split at the marker line "@@FILE@@": part 0 becomes poses.txt, part 1 points.txt,
// part 2 + k the image k.png (at most kMaxImages images); a missing part means a missing file. The
// marker is a text line so that the seeds stay readable and the fuzzer can learn it from them.
#include "fuzz_common.h"

#include <swba/io/directba_dataset.h>

#include <string>
#include <vector>

namespace
{
constexpr size_t kMaxImages = 4;
const std::string kMarker = "\n@@FILE@@\n";

std::vector<std::string> split_parts(const std::string& bytes)
{
	std::vector<std::string> parts;
	size_t begin = 0;
	while (parts.size() < 2 + kMaxImages)
	{
		const size_t at = bytes.find(kMarker, begin);
		if (at == std::string::npos)
		{
			parts.push_back(bytes.substr(begin));
			break;
		}
		parts.push_back(bytes.substr(begin, at - begin));
		begin = at + kMarker.size();
	}
	return parts;
}

std::string file_name(size_t part) { return part == 0 ? "poses.txt" : part == 1 ? "points.txt" : std::to_string(part - 2) + ".png"; }
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
	const auto parts = split_parts(swba::fuzz::as_text(data, size));
	for (size_t p = 0; p < 2 + kMaxImages; p++)
	{
		if (p < parts.size())
			swba::fuzz::write_scratch_file(file_name(p), parts[p]);
		else
			swba::fuzz::remove_scratch_file(file_name(p));
	}
	swba::fuzz::read_or_reject([] { (void)swba::io::read_directba_dataset(swba::fuzz::scratch_dir()); });
	return 0;
}
