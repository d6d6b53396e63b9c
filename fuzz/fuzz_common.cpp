#include "fuzz_common.h"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <new>
#include <unistd.h>

namespace swba::fuzz
{
namespace
{
void remove_scratch_dir()
{
	std::error_code ec;
	std::filesystem::remove_all(scratch_dir(), ec);
}
}  // namespace

void rejected(const std::exception& e)
{
	if (dynamic_cast<const std::bad_alloc*>(&e))
	{
		std::fprintf(stderr, "fuzz harness: allocation failure (%s): a finding\n", e.what());
		std::abort();
	}
	static const bool verbose = std::getenv("SWBA_FUZZ_VERBOSE") != nullptr;
	if (verbose) std::fprintf(stderr, "rejected: %s\n", e.what());
}

const std::string& scratch_dir()
{
	// Never destroyed: remove_scratch_dir runs from atexit after static destructors registered later.
	static const std::string& dir = *[] {
		auto* d = new std::string("/tmp/swba_fuzz_" + std::to_string(::getpid()));
		std::filesystem::create_directories(*d);
		std::atexit(remove_scratch_dir);
		return d;
	}();
	return dir;
}

std::string write_scratch_file(const std::string& name, const std::string& bytes)
{
	const std::string path = scratch_dir() + "/" + name;
	std::ofstream f(path, std::ios::binary | std::ios::trunc);
	f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
	f.close();
	if (!f)
	{
		std::fprintf(stderr, "fuzz harness: cannot write %s\n", path.c_str());
		std::abort();
	}
	return path;
}

void remove_scratch_file(const std::string& name) { std::remove((scratch_dir() + "/" + name).c_str()); }
}  // namespace swba::fuzz
