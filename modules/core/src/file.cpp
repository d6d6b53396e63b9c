#include <swba/core/file.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <cstdio>
#include <sstream>
#include <stdexcept>
#include <unistd.h>

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

namespace
{
std::string nul_note(std::size_t offset)
{
	return "not a text file (a NUL byte at byte " + std::to_string(offset) + ": binary data, e.g. a rawlog)";
}
}  // namespace

constexpr std::size_t kTextProbeBytes = 64 * 1024;

std::string binary_data_note(std::string_view text)
{
	const auto nul = text.substr(0, kTextProbeBytes).find('\0');
	return nul == std::string_view::npos ? "" : nul_note(nul);
}

std::string binary_data_note(std::istream& in)
{
	std::string head(kTextProbeBytes, '\0');
	in.read(head.data(), static_cast<std::streamsize>(head.size()));
	head.resize(static_cast<std::size_t>(in.gcount()));
	in.clear();
	in.seekg(0);
	return binary_data_note(std::string_view(head));
}

std::string read_text_file(const std::string& path, const std::string& what_file)
{
	std::ifstream f = open_input_file(path, std::ios::in | std::ios::binary, what_file);
	std::ostringstream text;
	text << f.rdbuf();
	if (f.bad()) fail(path, what_file, "read error");
	std::string s = text.str();
	const auto nul = s.find('\0');
	if (nul != std::string::npos) fail(path, what_file, nul_note(nul));
	return s;
}

void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& write,
						   std::ios::openmode mode)
{
	// A device or FIFO (/dev/stdout, /dev/full) is written in place: renaming over it would replace it.
	std::error_code ec;
	const auto type = std::filesystem::status(path, ec).type();
	const bool in_place = type != std::filesystem::file_type::not_found && type != std::filesystem::file_type::regular;
	const std::string tmp = in_place ? path : path + ".tmp." + std::to_string(::getpid());
	const auto failed = [&](int err) {
		if (!in_place) std::remove(tmp.c_str());
		throw std::runtime_error("cannot write '" + path + "': " + (err ? std::strerror(err) : "I/O error"));
	};
	errno = 0;
	std::ofstream f(tmp, mode | std::ios::out | (in_place ? std::ios::openmode{} : std::ios::trunc));
	if (!f) failed(errno);
	try
	{
		errno = 0;
		write(f);
	}
	catch (...)
	{
		f.close();
		if (!in_place) std::remove(tmp.c_str());
		throw;
	}
	if (!f) failed(errno);  // errno of the failed write, before anything else can reset it
	f.flush();
	if (!f) failed(errno);
	f.close();  // a full disk can show only here
	if (!f) failed(errno);
	if (!in_place && std::rename(tmp.c_str(), path.c_str()) != 0) failed(errno);
}

void write_text_file_atomically(const std::string& path, const std::string& text)
{
	write_file_atomically(path, [&](std::ostream& f) { f << text; });
}

void create_directory_or_throw(const std::string& dir, const std::string& what)
{
	std::error_code ec;
	std::filesystem::create_directories(dir, ec);
	if (ec || !std::filesystem::is_directory(dir))
		throw std::runtime_error("cannot create " + what + " '" + dir + "'" + (ec ? ": " + ec.message() : ""));
}
}  // namespace swba
