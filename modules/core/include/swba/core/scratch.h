/** \file scratch.h
 * Scratch memory for code that runs once per factor evaluation, where a heap allocation per call
 * costs more than the arithmetic (and far more under AddressSanitizer). */
#pragma once

#include <array>
#include <cstddef>
#include <vector>

namespace swba
{
/** n uninitialised values: on the stack when n <= N, else on the heap. */
template <typename T, std::size_t N>
class Scratch
{
   public:
	explicit Scratch(std::size_t n) : heap_(n > N ? n : 0) {}
	Scratch(const Scratch&) = delete;
	Scratch& operator=(const Scratch&) = delete;

	T* data() { return heap_.empty() ? stack_.data() : heap_.data(); }

   private:
	std::array<T, N> stack_;
	std::vector<T> heap_;
};
}  // namespace swba
