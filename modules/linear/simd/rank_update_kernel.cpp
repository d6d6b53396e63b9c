// One SIMD level's kernel of swba/linear/rank_update.h. Compiled once per level by
// modules/linear/CMakeLists.txt with that level's instruction-set flags and SWBA_SIMD_LEVEL set to its
// name (avx2, avx512); never part of the module's source glob.
#ifndef SWBA_SIMD_LEVEL
#error "SWBA_SIMD_LEVEL must name the SIMD level this translation unit is compiled for"
#endif

// Eigen is header-only: every template used here is instantiated in this translation unit with this
// level's packets, under the same mangled names as the baseline instantiations elsewhere in the
// library, and the linker would keep one of each. Renaming Eigen's namespace for this unit keeps its
// instantiations apart. Nothing else may include Eigen here, nor any Eigen type cross the interface.
// GCC 12 reports its own AVX-512 intrinsics' "undefined" idiom (avx512fintrin.h: `__m512d __Y = __Y;`)
// as maybe-uninitialized where Eigen's packets inline them; the warning is about the compiler's header.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

#define SWBA_SIMD_CONCAT2(a, b) a##b
#define SWBA_SIMD_CONCAT(a, b) SWBA_SIMD_CONCAT2(a, b)
#define Eigen SWBA_SIMD_CONCAT(swba_eigen_, SWBA_SIMD_LEVEL)
#include <Eigen/Core>

#include "../src/rank_update_kernels.h"

namespace swba::simd::SWBA_SIMD_LEVEL
{
void lower_rank_update(std::ptrdiff_t n, std::ptrdiff_t k, const double* U, std::ptrdiff_t ldu, const double* sign,
					   double* C, std::ptrdiff_t ldc)
{
	using Stride = Eigen::OuterStride<>;
	const Eigen::Map<const Eigen::MatrixXd, 0, Stride> u(U, n, k, Stride(ldu));
	const Eigen::Map<const Eigen::VectorXd> s(sign, k);
	Eigen::Map<Eigen::MatrixXd, 0, Stride> c(C, n, n, Stride(ldc));
	c.triangularView<Eigen::Lower>() += (u * s.asDiagonal()) * u.transpose();
}
}  // namespace swba::simd::SWBA_SIMD_LEVEL
