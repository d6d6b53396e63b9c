#include <swba/linear/rank_update.h>

#include "rank_update_kernels.h"

#include <algorithm>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace swba
{
namespace
{
using Kernel = void (*)(std::ptrdiff_t, std::ptrdiff_t, const double*, std::ptrdiff_t, const double*, double*,
					   std::ptrdiff_t);

/** The kernel of a SIMD level when this build has it and this CPU runs it, else nullptr (also for the
 * baseline, which is the Eigen expression of lower_rank_update itself). */
Kernel simd_kernel([[maybe_unused]] SimdLevel level)
{
#if defined(__x86_64__) && defined(__GNUC__)
	switch (level)
	{
#ifdef SWBA_SIMD_HAVE_AVX2
		case SimdLevel::Avx2:
			return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") ? &simd::avx2::lower_rank_update
																				   : nullptr;
#endif
#ifdef SWBA_SIMD_HAVE_AVX512
		case SimdLevel::Avx512:
			return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
						   __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512bw") &&
						   __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")
					   ? &simd::avx512::lower_rank_update
					   : nullptr;
#endif
		default:
			return nullptr;
	}
#else
	return nullptr;
#endif
}

bool cpu_runs(SimdLevel level) { return level == SimdLevel::Baseline || simd_kernel(level) != nullptr; }

/** The level to run, or the reason there is none (an invalid SWBA_SIMD). */
struct Choice
{
	SimdLevel level = SimdLevel::Baseline;
	std::string error;
};

Choice choose_level()
{
	const auto& levels = available_simd_levels();
	const char* env = std::getenv("SWBA_SIMD");
	if (env == nullptr || *env == '\0') return {levels.back(), {}};
	try
	{
		const SimdLevel wanted = parse_enum<SimdLevel>(env, "SWBA_SIMD level");
		if (std::find(levels.begin(), levels.end(), wanted) != levels.end()) return {wanted, {}};
		std::string names;
		for (SimdLevel l : levels) names += (names.empty() ? "" : ", ") + enum_name(l);
		return {SimdLevel::Baseline,
				"SWBA_SIMD=" + std::string(env) + ": not available in this build on this CPU (available: " + names + ")"};
	}
	catch (const std::invalid_argument& e)
	{
		return {SimdLevel::Baseline, e.what()};
	}
}

void check_shapes(const Eigen::Ref<Eigen::MatrixXd>& C, const Eigen::Ref<const Eigen::MatrixXd>& U,
				  const Eigen::Ref<const Eigen::VectorXd>& sign)
{
	if (C.rows() != C.cols() || U.rows() != C.rows() || U.cols() != sign.size())
		throw std::invalid_argument("lower_rank_update: C must be square, U have C's rows and sign U's columns");
}
}  // namespace

const std::vector<SimdLevel>& available_simd_levels()
{
	static const std::vector<SimdLevel> levels = [] {
		std::vector<SimdLevel> out;
		for (SimdLevel l : {SimdLevel::Baseline, SimdLevel::Avx2, SimdLevel::Avx512})
			if (cpu_runs(l)) out.push_back(l);
		return out;
	}();
	return levels;
}

SimdLevel active_simd_level()
{
	static const Choice choice = choose_level();
	if (!choice.error.empty()) throw std::invalid_argument(choice.error);
	return choice.level;
}

void lower_rank_update(Eigen::Ref<Eigen::MatrixXd> C, const Eigen::Ref<const Eigen::MatrixXd>& U,
					   const Eigen::Ref<const Eigen::VectorXd>& sign)
{
	lower_rank_update(active_simd_level(), C, U, sign);
}

void lower_rank_update(SimdLevel level, Eigen::Ref<Eigen::MatrixXd> C, const Eigen::Ref<const Eigen::MatrixXd>& U,
					   const Eigen::Ref<const Eigen::VectorXd>& sign)
{
	check_shapes(C, U, sign);
	if (!cpu_runs(level))
		throw std::invalid_argument("lower_rank_update: SIMD level " + enum_name(level) + " not available");
	if (C.rows() == 0 || sign.size() == 0) return;
	if (const Kernel kernel = simd_kernel(level))
		kernel(C.rows(), U.cols(), U.data(), U.outerStride(), sign.data(), C.data(), C.outerStride());
	else
		C.triangularView<Eigen::Lower>() += (U * sign.asDiagonal()) * U.transpose();
}
}  // namespace swba
