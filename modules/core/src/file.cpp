#include <swba/core/file.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>

namespace swba
{
namespace
{
[[noreturn]] void fail(const std::string& path, const std::string& what_file, const std::string& what)
{
	throw std::runtime_error((what_file.empty() ? "" : what_file + " ") + "'" + path + "': " + what);
}
}  // namespace

void check_input_file(const std::string& path, const std::string& what_file)
{
	namespace fs = std::filesystem;
	if (path.empty()) throw std::runtime_error((what_file.empty() ? "input" : what_file) + ": empty file name");
	std::error_code ec;
	const fs::file_status st = fs::status(path, ec);
	if (st.type() == fs::file_type::not_found) fail(path, what_file, "file does not exist");
	if (ec) fail(path, what_file, "cannot access: " + ec.message());
	if (st.type() == fs::file_type::directory) fail(path, what_file, "is a directory, not a file");
	if (st.type() != fs::file_type::regular) fail(path, what_file, "is not a regular file (a FIFO, device or socket)");
}

std::ifstream open_input_file(const std::string& path, std::ios::openmode mode, const std::string& what_file)
{
	check_input_file(path, what_file);
	errno = 0;
	std::ifstream f(path, mode);
	if (!f) fail(path, what_file, std::string("cannot open: ") + (errno ? std::strerror(errno) : "unknown error"));
	return f;
}
}  // namespace swba
