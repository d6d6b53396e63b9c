/** \file rank_update.h
 * The symmetric rank-k update of one triangle, tril(C) += U diag(s) Uᵀ, run by the kernel of the
 * widest SIMD instruction set that this build has and this CPU runs.
 *
 * Why a dispatcher: this update is the arithmetic that grows with the map in a SLAM window (the stored
 * landmarks' covariance: O(n² k) per step, compute-bound once k is a few dozen). A portable x86-64
 * build has SSE2 only (two doubles per instruction, no fused multiply-add) and leaves most of a current
 * core idle; AVX2 with FMA runs the same product about 3× faster, AVX-512 about 4×
 * (doc/benchmarks/run.md). Eigen chooses its packets when it is compiled, so each level is the same Eigen
 * expression compiled in a translation unit of its own with that level's flags (Eigen's templates
 * there live in a namespace of their own: with one name, the linker would merge them with the
 * baseline's), and the CPU's features are read once.
 *
 * Levels agree up to rounding (fused multiply-adds, the order of partial sums); a machine runs one
 * level, so output is deterministic on it, whatever the thread count. The environment variable
 * SWBA_SIMD (baseline, avx2 or avx512) chooses a narrower level, e.g. to reproduce another machine's
 * digits or to measure the kernels against each other. */
#pragma once

#include <swba/core/names.h>

#include <Eigen/Core>
#include <array>
#include <vector>

namespace swba
{
/** The instruction sets of the kernels (x86-64: baseline = SSE2; avx2 = AVX2 + FMA; avx512 = AVX-512
 * F, DQ, VL, BW with AVX2 + FMA). Other architectures have the baseline, compiled for their default. */
enum class SimdLevel { Baseline, Avx2, Avx512 };
constexpr std::array<EnumName<SimdLevel>, 3> enum_names(SimdLevel)
{
	return {{{SimdLevel::Baseline, "baseline"}, {SimdLevel::Avx2, "avx2"}, {SimdLevel::Avx512, "avx512"}}};
}

/** The levels this build has a kernel for and this CPU runs, narrowest first (the baseline always). */
const std::vector<SimdLevel>& available_simd_levels();

/** The level lower_rank_update(C, U, sign) runs: the widest available, or SWBA_SIMD's. Throws
 * std::invalid_argument (once read, at every call) if SWBA_SIMD names no level or one not available. */
SimdLevel active_simd_level();

/** tril(C) += U diag(sign) Uᵀ over the square C: its lower triangle (diagonal included) is updated,
 * its strict upper triangle is neither read nor written. U has C's rows and sign.size() columns. */
void lower_rank_update(Eigen::Ref<Eigen::MatrixXd> C, const Eigen::Ref<const Eigen::MatrixXd>& U,
					   const Eigen::Ref<const Eigen::VectorXd>& sign);

/** The same with the kernel of `level` (tests, benchmarks); throws std::invalid_argument if it is not
 * available. */
void lower_rank_update(SimdLevel level, Eigen::Ref<Eigen::MatrixXd> C, const Eigen::Ref<const Eigen::MatrixXd>& U,
					   const Eigen::Ref<const Eigen::VectorXd>& sign);
}  // namespace swba
