// Small dense block kernels with compile-time sizes for the common block sizes and a dynamic
// fallback. All blocks are row-major.
//
// The fixed-size kernels are plain loops (no Eigen GEMM: for sizes such as 9×9×3 Eigen's product
// switches to its blocked general path, which packs and is slow for tiny blocks). Each output
// coefficient is a sum formed in a local and then added once, so the rounding does not depend on how
// the compiler vectorises across the output row.
#pragma once

#include <Eigen/Core>

#include <type_traits>

namespace swba::detail
{
/** Row-major matrix type (column vectors stay column-major, as Eigen requires). */
template <int R, int C>
using RM = Eigen::Matrix<double, R, C, (C == 1 && R != 1) ? Eigen::ColMajor : Eigen::RowMajor>;

/** Calls f(std::integral_constant<int, N>) with N the first of Ns equal to n, or Eigen::Dynamic. */
template <int... Ns, typename F>
inline void dispatch_among(int n, F&& f)
{
	const bool hit = ((n == Ns && (f(std::integral_constant<int, Ns>()), true)) || ...);
	if (!hit) f(std::integral_constant<int, Eigen::Dynamic>());
}

/** Tangent (block) sizes with a compiled kernel: 1, 3, 6, 9; others are Eigen::Dynamic. */
template <typename F>
inline void dispatch_size(int n, F&& f)
{
	dispatch_among<1, 3, 6, 9>(n, f);
}

/** Residual dimensions with a compiled kernel: 1, 2, 3, 6. */
template <typename F>
inline void dispatch_rows(int m, F&& f)
{
	dispatch_among<1, 2, 3, 6>(m, f);
}

/** N if fixed, else the run-time n. */
template <int N>
constexpr int dim_or(int n)
{
	return N > 0 ? N : n;
}

/** C (na×nb) += Aᵀ B with A m×na, B m×nb. */
inline void add_AtB(const double* A, const double* B, int m, int na, int nb, double* C)
{
	dispatch_rows(m, [&](auto MM) {
		dispatch_size(na, [&](auto NA) {
			dispatch_size(nb, [&](auto NB) {
				constexpr int M = decltype(MM)::value, Na = decltype(NA)::value, Nb = decltype(NB)::value;
				if constexpr (M > 0 && Na > 0 && Nb > 0)
				{
					for (int i = 0; i < Na; i++)
						for (int j = 0; j < Nb; j++)
						{
							double acc = A[i] * B[j];
							for (int r = 1; r < M; r++) acc += A[r * Na + i] * B[r * Nb + j];
							C[i * Nb + j] += acc;
						}
				}
				else if constexpr (Na > 0 && Nb > 0)
				{
					// Many rows (a marginalisation prior), small blocks: accumulate row by row in a
					// local block (GEMM's packing costs more than the product at these sizes).
					double acc[Na * Nb] = {};
					for (int r = 0; r < m; r++)
					{
						const double* a = A + r * Na;
						const double* b = B + r * Nb;
						for (int i = 0; i < Na; i++)
							for (int j = 0; j < Nb; j++) acc[i * Nb + j] += a[i] * b[j];
					}
					for (int k = 0; k < Na * Nb; k++) C[k] += acc[k];
				}
				else
				{
					Eigen::Map<const RM<Eigen::Dynamic, Eigen::Dynamic>> a(A, m, na);
					Eigen::Map<const RM<Eigen::Dynamic, Eigen::Dynamic>> b(B, m, nb);
					Eigen::Map<RM<Eigen::Dynamic, Eigen::Dynamic>> c(C, na, nb);
					c.noalias() += a.transpose() * b;
				}
			});
		});
	});
}

/** y (n) += Aᵀ r with A m×n. */
inline void add_Atr(const double* A, const double* r, int m, int n, double* y)
{
	dispatch_rows(m, [&](auto MM) {
		dispatch_size(n, [&](auto NN) {
			constexpr int M = decltype(MM)::value, N = decltype(NN)::value;
			if constexpr (M > 0 && N > 0)
			{
				for (int i = 0; i < N; i++)
				{
					double acc = A[i] * r[0];
					for (int k = 1; k < M; k++) acc += A[k * N + i] * r[k];
					y[i] += acc;
				}
			}
			else if constexpr (N > 0)
			{
				double acc[N] = {};
				for (int k = 0; k < m; k++)
					for (int i = 0; i < N; i++) acc[i] += A[k * N + i] * r[k];
				for (int i = 0; i < N; i++) y[i] += acc[i];
			}
			else
			{
				Eigen::Map<const RM<Eigen::Dynamic, Eigen::Dynamic>> a(A, m, n);
				Eigen::Map<const Eigen::VectorXd> rv(r, m);
				Eigen::Map<Eigen::VectorXd> yv(y, n);
				yv.noalias() += a.transpose() * rv;
			}
		});
	});
}

/** xᵀ A y with A n×m (row-major); run-time sizes (used once per block per iteration). */
inline double quadratic_form(const double* x, const double* A, const double* y, int n, int m)
{
	double s = 0;
	for (int i = 0; i < n; i++)
	{
		double row = 0;
		for (int j = 0; j < m; j++) row += A[i * m + j] * y[j];
		s += x[i] * row;
	}
	return s;
}
}  // namespace swba::detail
