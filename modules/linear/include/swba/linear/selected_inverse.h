/** \file selected_inverse.h
 * Entries of A⁻¹ on the sparsity pattern of A's Cholesky factor, from the factor alone (the Takahashi
 * recurrence: Takahashi, Fagan & Chen 1973; Erisman & Tinney 1975). With A = P⁻¹ L Lᵀ P⁻ᵀ and Z = (L Lᵀ)⁻¹,
 * Z L = L⁻ᵀ is upper triangular, so column j of that product gives, from the last column to the first,
 *   Z_ij = −(1/L_jj) Σ_{k>j, k∈L_*j} Z_ik L_kj            (i > j, i ∈ L_*j)
 *   Z_jj = (1/L_jj) (1/L_jj − Σ_{k>j, k∈L_*j} Z_kj L_kj),
 * and every Z_ik it reads lies in the pattern already computed (the rows of a factor's column are a
 * clique of the filled graph). The pattern holds every pair of variables that share a block of A, so
 * every marginal block and every joint block of variables that share a factor is in it.
 * Cost: work() multiply-adds, Σ_j Σ_{k∈L_*j, k>j} |L_*k| (≈ n³/6 for a dense factor, far less for a
 * sparse one), against 2·nnz(L) per wanted column for the triangular solves. */
#pragma once

#include <vector>

namespace swba
{
class SelectedInverse
{
   public:
	SelectedInverse() = default;
	/** From a factor L of P A Pᵀ in compressed columns: n columns, col_begin (n + 1 entries), rows
	 * strictly ascending in each column with the diagonal first, values; perm[k] is the row of A that is
	 * row k of the factor (nullptr: identity). Throws std::invalid_argument if the pattern is not a
	 * Cholesky factor's (a column without its diagonal first, unsorted rows, a fill entry missing). */
	SelectedInverse(int n, const int* col_begin, const int* rows, const double* values, const int* perm);

	/** The multiply-adds of the recurrence on that pattern (the inner loop's length, summed). */
	static double work(int n, const int* col_begin, const int* rows);

	int dim() const { return static_cast<int>(iperm_.size()); }
	/** A⁻¹(r, c) (either triangle) when (r, c) is in the factor's pattern; false otherwise. */
	bool find(int r, int c, double& value) const;

   private:
	/** Index of factor entry (a ≥ b) in rows_/z_, or −1. */
	long position(int a, int b) const;

	std::vector<int> col_begin_, rows_, iperm_;
	std::vector<double> z_;
};
}  // namespace swba
