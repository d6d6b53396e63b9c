// ScopedMemoryBudget: an allocation beyond the budget throws std::bad_alloc (also through MRPT's
// aligned allocator, which returns null by itself), and the budget ends with its scope.
#include <swba/core/memory_budget.h>

#include <mrpt/core/aligned_allocator.h>

#include <gtest/gtest.h>

#include <cstdint>
#include <new>
#include <vector>

namespace
{
constexpr std::uint64_t kMiB = std::uint64_t(1) << 20;

/** Allocates n bytes through std::vector and lets the pointer escape: clang removes an allocation whose
 *  result is never used (a new/delete pair may be elided), and the test would then allocate nothing. */
void allocate(std::uint64_t n)
{
	std::vector<char> v(n);
	asm volatile("" : : "r"(v.data()) : "memory");
}

TEST(MemoryBudget, AnAllocationBeyondTheBudgetThrowsAndTheBudgetEndsWithItsScope)
{
	if (!swba::ScopedMemoryBudget::supported()) GTEST_SKIP() << "no address-space budget in sanitizer builds";
	{
		swba::ScopedMemoryBudget budget(64 * kMiB);
		ASSERT_TRUE(budget.active());
		EXPECT_THROW(allocate(512 * kMiB), std::bad_alloc);
		EXPECT_NO_THROW(allocate(8 * kMiB));  // within the budget
	}
	EXPECT_NO_THROW(allocate(512 * kMiB));  // the cap is gone
}

TEST(MemoryBudget, MrptAlignedAllocatorThrowsInsteadOfReturningNull)
{
	if (!swba::ScopedMemoryBudget::supported()) GTEST_SKIP() << "no address-space budget in sanitizer builds";
	swba::ScopedMemoryBudget budget(64 * kMiB);
	ASSERT_TRUE(budget.active());
	// MRPT's own definition returns null here and std::vector writes through it (a crash).
	std::vector<float, mrpt::aligned_allocator_cpp11<float>> v;
	EXPECT_THROW(v.resize(std::size_t(256) * kMiB), std::bad_alloc);
}

TEST(MemoryBudget, NestedBudgetKeepsTheTighterLimit)
{
	if (!swba::ScopedMemoryBudget::supported()) GTEST_SKIP() << "no address-space budget in sanitizer builds";
	swba::ScopedMemoryBudget outer(64 * kMiB);
	ASSERT_TRUE(outer.active());
	swba::ScopedMemoryBudget inner(4096 * kMiB);  // looser: left inactive, the outer cap holds
	EXPECT_FALSE(inner.active());
	EXPECT_THROW(allocate(512 * kMiB), std::bad_alloc);
}
}  // namespace
