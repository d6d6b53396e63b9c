/** \file memory_budget.h
 * A memory budget for reading untrusted files through code that allocates what the file declares
 * (MRPT 2.5's deserialisation resizes strings, vectors and deques to 32-bit counts read from the
 * stream, before it can notice that the data is not there: doc/benchmarks/fuzzing.md, "MRPT findings"). */
#pragma once

#include <cstddef>
#include <cstdint>

namespace swba
{
/** 256 MiB + per_byte · data_bytes: a budget for reading `data_bytes` of a file whose decoded size
 * is at most `per_byte` times its own; saturates at 2^64 − 2 instead of wrapping. */
std::uint64_t scaled_memory_budget(std::uint64_t data_bytes, std::uint64_t per_byte);

/** While alive, caps the process's address space (RLIMIT_AS) at its size when constructed plus
 * `bytes`, so that an allocation beyond the budget fails with std::bad_alloc instead of taking the
 * machine's memory; the previous limit is restored on destruction. A lower limit already in place is
 * kept. Process-wide: other threads allocating meanwhile share the budget.
 *
 * Inactive (active() false, nothing changed) when the build uses AddressSanitizer, MemorySanitizer or
 * ThreadSanitizer (they reserve terabytes of address space and abort on a failed allocation instead
 * of throwing), when the current address-space size cannot be read (/proc/self/statm) or when
 * setrlimit fails. */
class ScopedMemoryBudget
{
   public:
	explicit ScopedMemoryBudget(std::uint64_t bytes);
	~ScopedMemoryBudget();
	ScopedMemoryBudget(const ScopedMemoryBudget&) = delete;
	ScopedMemoryBudget& operator=(const ScopedMemoryBudget&) = delete;

	/** True when the cap is in place. */
	bool active() const { return active_; }
	/** The budget asked for, in bytes. */
	std::uint64_t bytes() const { return bytes_; }

	/** False in builds where no budget can be set (see the class comment). */
	static bool supported();

   private:
	std::uint64_t bytes_;
	bool active_ = false;
	std::uint64_t old_soft_ = 0, old_hard_ = 0;
};
}  // namespace swba
