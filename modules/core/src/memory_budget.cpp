#include <swba/core/memory_budget.h>

#include <mrpt/core/aligned_allocator.h>

#include <atomic>
#include <cstdlib>
#include <fstream>
#include <new>

#include <sys/resource.h>
#include <unistd.h>

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define SWBA_SANITIZER_OWNS_ADDRESS_SPACE 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(memory_sanitizer) || __has_feature(thread_sanitizer)
#define SWBA_SANITIZER_OWNS_ADDRESS_SPACE 1
#endif
#endif

namespace
{
std::atomic<int> active_budgets{0};
}

/* MRPT 2.5's aligned allocator (mrpt/core/aligned_allocator.h, used by its containers of floats)
 * returns the null pointer of mrpt::aligned_malloc when an allocation fails instead of throwing
 * std::bad_alloc as an allocator must, and its callers write through it (a crash instead of an
 * error). This definition interposes MRPT's (same rounding of the size to the alignment, same
 * ::aligned_alloc, so mrpt::aligned_free stays ::free) and throws std::bad_alloc on failure while a
 * memory budget is active, which is when failures are expected. Outside a budget it behaves exactly
 * as MRPT's. */
void* mrpt::aligned_malloc(size_t size, size_t alignment)
{
	if (alignment != 0 && size % alignment != 0) size = (size / alignment + 1) * alignment;
	void* p = ::aligned_alloc(alignment, size);
	if (p == nullptr && size != 0 && active_budgets.load() > 0) throw std::bad_alloc();
	return p;
}

namespace swba
{
std::uint64_t scaled_memory_budget(std::uint64_t data_bytes, std::uint64_t per_byte)
{
	constexpr std::uint64_t kBase = std::uint64_t(256) << 20;
	const std::uint64_t max = ~std::uint64_t(0);
	if (data_bytes > (max - kBase) / per_byte) return max - 1;
	return kBase + per_byte * data_bytes;
}

namespace
{
/** The process's address-space size in bytes (VmSize), 0 when unknown. */
std::uint64_t address_space_size()
{
	std::ifstream statm("/proc/self/statm");
	std::uint64_t pages = 0;
	if (!(statm >> pages)) return 0;
	const long page = sysconf(_SC_PAGESIZE);
	return page > 0 ? pages * static_cast<std::uint64_t>(page) : 0;
}
}  // namespace

bool ScopedMemoryBudget::supported()
{
#ifdef SWBA_SANITIZER_OWNS_ADDRESS_SPACE
	return false;
#else
	return true;
#endif
}

ScopedMemoryBudget::ScopedMemoryBudget(std::uint64_t bytes) : bytes_(bytes)
{
	if (!supported()) return;
	rlimit old{};
	if (getrlimit(RLIMIT_AS, &old) != 0) return;
	const std::uint64_t size = address_space_size();
	if (size == 0) return;
	const std::uint64_t cap = size + bytes;
	if (old.rlim_cur != RLIM_INFINITY && old.rlim_cur <= cap) return;  // a tighter limit is in place
	const rlimit now{static_cast<rlim_t>(cap), old.rlim_max};
	if (setrlimit(RLIMIT_AS, &now) != 0) return;
	old_soft_ = old.rlim_cur;
	old_hard_ = old.rlim_max;
	active_ = true;
	active_budgets++;
}

ScopedMemoryBudget::~ScopedMemoryBudget()
{
	if (!active_) return;
	active_budgets--;
	const rlimit old{static_cast<rlim_t>(old_soft_), static_cast<rlim_t>(old_hard_)};
	setrlimit(RLIMIT_AS, &old);
}
}  // namespace swba
