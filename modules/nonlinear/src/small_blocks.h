// Small dense block kernels with compile-time sizes for the common block sizes (1, 2, 3, 6, 9) and a
// dynamic fallback. All blocks are row-major.
#pragma once

#include <Eigen/Core>

namespace swba::detail
{
/** Row-major matrix type (column vectors stay column-major, as Eigen requires). */
template <int R, int C>
using RM = Eigen::Matrix<double, R, C, (C == 1 && R != 1) ? Eigen::ColMajor : Eigen::RowMajor>;

/** Calls f(std::integral_constant<int, N>) with N the compile-time size of n, or Eigen::Dynamic. */
template <typename F>
inline void dispatch_size(int n, F&& f)
{
	switch (n)
	{
		case 1: f(std::integral_constant<int, 1>()); break;
		case 3: f(std::integral_constant<int, 3>()); break;
		case 6: f(std::integral_constant<int, 6>()); break;
		case 9: f(std::integral_constant<int, 9>()); break;
		default: f(std::integral_constant<int, Eigen::Dynamic>()); break;
	}
}

/** C (na×nb) += Aᵀ B with A m×na, B m×nb. */
inline void add_AtB(const double* A, const double* B, int m, int na, int nb, double* C)
{
	dispatch_size(na, [&](auto NA) {
		dispatch_size(nb, [&](auto NB) {
			constexpr int Na = decltype(NA)::value, Nb = decltype(NB)::value;
			Eigen::Map<const RM<Eigen::Dynamic, Na>> a(A, m, na);
			Eigen::Map<const RM<Eigen::Dynamic, Nb>> b(B, m, nb);
			Eigen::Map<RM<Na, Nb>> c(C, na, nb);
			c.noalias() += a.transpose() * b;
		});
	});
}

/** y (n) += Aᵀ r with A m×n. */
inline void add_Atr(const double* A, const double* r, int m, int n, double* y)
{
	Eigen::Map<const RM<Eigen::Dynamic, Eigen::Dynamic>> a(A, m, n);
	Eigen::Map<const Eigen::VectorXd> rv(r, m);
	Eigen::Map<Eigen::VectorXd> yv(y, n);
	yv.noalias() += a.transpose() * rv;
}

/** C (na×nb) op= A (na×nl) · Bᵀ (B nb×nl); sign = −1 subtracts. */
inline void sub_ABt(const double* A, const double* B, int na, int nb, int nl, double* C)
{
	dispatch_size(na, [&](auto NA) {
		dispatch_size(nb, [&](auto NB) {
			dispatch_size(nl, [&](auto NL) {
				constexpr int Na = decltype(NA)::value, Nb = decltype(NB)::value, Nl = decltype(NL)::value;
				Eigen::Map<const RM<Na, Nl>> a(A, na, nl);
				Eigen::Map<const RM<Nb, Nl>> b(B, nb, nl);
				Eigen::Map<RM<Na, Nb>> c(C, na, nb);
				c.noalias() -= a * b.transpose();
			});
		});
	});
}

/** C (na×nl) = A (na×nl) · S (nl×nl). */
inline void set_AS(const double* A, const double* S, int na, int nl, double* C)
{
	dispatch_size(na, [&](auto NA) {
		dispatch_size(nl, [&](auto NL) {
			constexpr int Na = decltype(NA)::value, Nl = decltype(NL)::value;
			Eigen::Map<const RM<Na, Nl>> a(A, na, nl);
			Eigen::Map<const RM<Nl, Nl>> s(S, nl, nl);
			Eigen::Map<RM<Na, Nl>> c(C, na, nl);
			c.noalias() = a * s;
		});
	});
}

/** y (na) += sign · A (na×nl) x (nl). */
inline void add_Ax(const double* A, const double* x, int na, int nl, double sign, double* y)
{
	Eigen::Map<const RM<Eigen::Dynamic, Eigen::Dynamic>> a(A, na, nl);
	Eigen::Map<const Eigen::VectorXd> xv(x, nl);
	Eigen::Map<Eigen::VectorXd> yv(y, na);
	yv.noalias() += sign * (a * xv);
}

/** y (nl) += sign · Aᵀ x with A na×nl, x na. */
inline void add_Atx(const double* A, const double* x, int na, int nl, double sign, double* y)
{
	Eigen::Map<const RM<Eigen::Dynamic, Eigen::Dynamic>> a(A, na, nl);
	Eigen::Map<const Eigen::VectorXd> xv(x, na);
	Eigen::Map<Eigen::VectorXd> yv(y, nl);
	yv.noalias() += sign * (a.transpose() * xv);
}
}  // namespace swba::detail
