#include <gtest/gtest.h>
#include <swba/core/scratch.h>

#include <cstdint>

namespace swba
{
namespace
{
// Fills n values and reads them back: a buffer shorter than n fails under the sanitizers, and the two
// paths are told apart by where the data lives (inside the object or not).
template <std::size_t N>
void check(std::size_t n, bool on_stack)
{
	Scratch<double, N> s(n);
	for (std::size_t i = 0; i < n; i++) s.data()[i] = static_cast<double>(i);
	for (std::size_t i = 0; i < n; i++) EXPECT_EQ(s.data()[i], static_cast<double>(i));
	const auto p = reinterpret_cast<std::uintptr_t>(s.data());
	const auto o = reinterpret_cast<std::uintptr_t>(&s);
	EXPECT_EQ(on_stack, p >= o && p < o + sizeof(s)) << "n = " << n << ", N = " << N;
}
}  // namespace

TEST(Scratch, HoldsUpToNInsideAndMoreOnTheHeap)
{
	check<8>(0, true);
	check<8>(8, true);
	check<8>(9, false);
	check<8>(1000, false);
}
}  // namespace swba
