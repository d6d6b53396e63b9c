// Replay driver: runs LLVMFuzzerTestOneInput once per file named on the command line (directories:
// every regular file in them, sorted), so that the committed seed and regression corpora run as
// ordinary tests in builds without libFuzzer. Prints one line per file; exit status 0 when every
// input was handled (a finding crashes, aborts or trips a sanitizer instead), 2 on a usage or I/O error.
// Without a sanitizer the address space is capped at kAddressSpaceLimit, so that an input asking for
// gigabytes fails with std::bad_alloc (a finding, see fuzz_common.h) rather than exhausting the machine;
// under ASan, which reserves terabytes of shadow space, the cap is left to ASan's allocator.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>
#include <sys/resource.h>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

namespace fs = std::filesystem;

#if defined(__SANITIZE_ADDRESS__)
#define SWBA_REPLAY_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define SWBA_REPLAY_ASAN 1
#endif
#endif

int main(int argc, char** argv)
{
#ifndef SWBA_REPLAY_ASAN
	constexpr rlim_t kAddressSpaceLimit = rlim_t(4) << 30;  // 4 GiB: the replays need well under 1
	const rlimit limit{kAddressSpaceLimit, kAddressSpaceLimit};
	setrlimit(RLIMIT_AS, &limit);
#endif
	std::vector<fs::path> files;
	for (int i = 1; i < argc; i++)
	{
		std::error_code ec;
		if (fs::is_directory(argv[i], ec))
		{
			for (const auto& e : fs::directory_iterator(argv[i]))
				if (e.is_regular_file()) files.push_back(e.path());
		}
		else if (fs::is_regular_file(argv[i], ec))
			files.emplace_back(argv[i]);
		else
		{
			std::fprintf(stderr, "replay: %s: no such file or directory\n", argv[i]);
			return 2;
		}
	}
	std::sort(files.begin(), files.end());
	for (const auto& f : files)
	{
		std::ifstream in(f, std::ios::binary);
		const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
		if (in.bad())
		{
			std::fprintf(stderr, "replay: cannot read %s\n", f.c_str());
			return 2;
		}
		std::printf("replay: %s (%zu bytes)\n", f.c_str(), bytes.size());
		std::fflush(stdout);
		LLVMFuzzerTestOneInput(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
	}
	std::printf("replay: %zu inputs handled\n", files.size());
	return 0;
}
