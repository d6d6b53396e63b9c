/** \file rank_update_kernels.h
 * (private to the linear module) The per-level kernels of rank_update.h, one namespace per level, over
 * raw column-major storage: each is compiled in its own translation unit (simd/rank_update_kernel.cpp)
 * whose Eigen types are not the rest of the library's, so nothing Eigen crosses this interface. */
#pragma once

#include <cstddef>

namespace swba::simd
{
#define SWBA_DECLARE_RANK_UPDATE_KERNEL(level)                                                                  \
	namespace level                                                                                               \
	{                                                                                                             \
	/** tril(C) += U diag(sign) Uᵀ; C is n × n with leading dimension ldc, U n × k with ldu. */                  \
	void lower_rank_update(std::ptrdiff_t n, std::ptrdiff_t k, const double* U, std::ptrdiff_t ldu, const double* sign, \
						   double* C, std::ptrdiff_t ldc);                                                      \
	}
SWBA_DECLARE_RANK_UPDATE_KERNEL(avx2)
SWBA_DECLARE_RANK_UPDATE_KERNEL(avx512)
#undef SWBA_DECLARE_RANK_UPDATE_KERNEL
}  // namespace swba::simd
