#include "decoder_probe.h"

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/serialization/CArchive.h>

#include <cerrno>
#include <csignal>
#include <cstring>
#include <fcntl.h>
#include <fstream>
#include <stdexcept>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

// Sanitizer runtimes call it on a fatal report; weak, so null when no sanitizer is linked.
extern "C" __attribute__((weak)) void __sanitizer_set_death_callback(void (*callback)(void));

namespace swba::io::detail
{
namespace
{
/** VmData of this process in bytes (0 if it cannot be read). */
std::uint64_t data_segment_bytes()
{
	std::ifstream status("/proc/self/status");
	std::string key;
	while (status >> key)
	{
		if (key == "VmData:")
		{
			std::uint64_t kib = 0;
			status >> kib;
			return kib << 10;
		}
		status.ignore(1 << 12, '\n');
	}
	return 0;
}

void cap_data_segment(std::uint64_t budget_bytes)
{
	if (budget_bytes == 0) return;
	const std::uint64_t now = data_segment_bytes();
	rlimit lim{};
	if (now == 0 || getrlimit(RLIMIT_DATA, &lim) != 0) return;
	const std::uint64_t want = now > RLIM_INFINITY - budget_bytes ? RLIM_INFINITY : now + budget_bytes;
	if (lim.rlim_cur != RLIM_INFINITY && lim.rlim_cur <= want) return;  // a lower cap already
	lim.rlim_cur = want;
	(void)setrlimit(RLIMIT_DATA, &lim);
}

void write_all(int fd, const void* data, std::size_t n)
{
	const char* p = static_cast<const char*>(data);
	while (n > 0)
	{
		const ssize_t w = ::write(fd, p, n);
		if (w < 0 && errno == EINTR) continue;
		if (w <= 0) return;
		p += w;
		n -= static_cast<std::size_t>(w);
	}
}

/** The child: reports the index of each entry before decoding it; never returns. */
[[noreturn]] void decode_all(const std::string& path, std::uint64_t budget_bytes, std::uint64_t max_entries,
							 int report_fd)
{
	// The child's death is the parent's datum, not a crash of the program: no crash handler of the
	// parent's (a fuzzer's, a sanitizer's report hook) may act on it.
	for (const int sig : {SIGSEGV, SIGBUS, SIGILL, SIGFPE, SIGABRT}) std::signal(sig, SIG_DFL);
	if (__sanitizer_set_death_callback) __sanitizer_set_death_callback(nullptr);
	const int devnull = ::open("/dev/null", O_WRONLY);
	if (devnull >= 0)
	{
		::dup2(devnull, STDOUT_FILENO);
		::dup2(devnull, STDERR_FILENO);
	}
	cap_data_segment(budget_bytes);
	try
	{
		mrpt::io::CFileGZInputStream f;
		std::string error;
		if (f.open(path, error))
		{
			auto arch = mrpt::serialization::archiveFrom(f);
			for (std::uint64_t entry = 0; entry < max_entries; entry++)
			{
				write_all(report_fd, &entry, sizeof entry);
				mrpt::serialization::CSerializable::Ptr obj;
				arch >> obj;
			}
		}
	}
	catch (...)
	{
		// The end of the data, or damage the parent's own reading reports with its context.
	}
	::_exit(0);  // no destructors, atexit handlers or leak checks of the parent's state
}

std::string describe(int status)
{
	if (WIFSIGNALED(status))
		return "killed by signal " + std::to_string(WTERMSIG(status)) + " (" + strsignal(WTERMSIG(status)) + ")";
	return "ended with exit status " + std::to_string(WEXITSTATUS(status)) +
		" (as a sanitizer build ends on a crash or on an allocation beyond the budget)";
}
}  // namespace

std::optional<DecoderDeath> probe_decoder_in_child(const std::string& path, std::uint64_t budget_bytes,
												   std::uint64_t max_entries)
{
	int fds[2];
	if (::pipe(fds) != 0) throw std::runtime_error(std::string("cannot create a pipe: ") + std::strerror(errno));
	const pid_t pid = ::fork();
	if (pid < 0)
	{
		const int e = errno;
		::close(fds[0]);
		::close(fds[1]);
		throw std::runtime_error(std::string("cannot fork the decoding probe: ") + std::strerror(e));
	}
	if (pid == 0)
	{
		::close(fds[0]);
		decode_all(path, budget_bytes, max_entries, fds[1]);
	}
	::close(fds[1]);
	std::uint64_t last = 0, value = 0;
	std::size_t have = 0;
	for (;;)
	{
		const ssize_t r = ::read(fds[0], reinterpret_cast<char*>(&value) + have, sizeof value - have);
		if (r < 0 && errno == EINTR) continue;
		if (r <= 0) break;
		have += static_cast<std::size_t>(r);
		if (have == sizeof value)
		{
			last = value;
			have = 0;
		}
	}
	::close(fds[0]);
	int status = 0;
	while (::waitpid(pid, &status, 0) < 0)
	{
		if (errno == ECHILD) return std::nullopt;  // SIGCHLD ignored by the application: the child was reaped
		if (errno != EINTR) throw std::runtime_error(std::string("waiting for the decoding probe: ") + std::strerror(errno));
	}
	if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return std::nullopt;
	return DecoderDeath{static_cast<std::size_t>(last), describe(status)};
}
}  // namespace swba::io::detail
