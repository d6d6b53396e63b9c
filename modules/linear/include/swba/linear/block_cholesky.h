/** \file block_cholesky.h
 * Cholesky solvers for a symmetric positive-definite matrix given as square blocks on a fixed
 * block-sparsity pattern (the reduced camera system, or a full pose-graph Hessian).
 * Two back ends behind one interface: dense LLT (Eigen) and supernodal sparse LLT (SuiteSparse
 * CHOLMOD through Eigen's CholmodSupport, analysed once per pattern, factorized per call).
 * CHOLMOD types never appear in this header. */
#pragma once

#include <swba/linear/selected_inverse.h>

#include <memory>
#include <utility>
#include <vector>

namespace swba
{
/** Block sparsity of a symmetric matrix: block sizes and the upper-triangular block pairs (i ≤ j),
 * every diagonal pair (i, i) included. */
struct BlockPattern
{
	std::vector<int> block_sizes;
	std::vector<std::pair<int, int>> upper_blocks;  ///< sorted, unique, i ≤ j
	std::vector<int> offsets() const;
	int dim() const;
};

class BlockCholesky
{
   public:
	virtual ~BlockCholesky() = default;
	/** Factorizes the matrix whose upper blocks are `blocks[k]` (row-major, sizes of
	 * upper_blocks[k]; a diagonal block must be full and symmetric). Returns false if not SPD. */
	virtual bool factorize(const std::vector<const double*>& blocks) = 0;
	/** Solves A x = b in place (after a successful factorize). */
	virtual void solve(double* b_inout) const = 0;
	/** Solves A X = B in place for `ncols` right-hand sides stored column after column (column-major,
	 * dim() rows): one pass through the factor for all of them (CHOLMOD's supernodal solve of a block). */
	virtual void solve_columns(double* B_inout, int ncols) const = 0;
	virtual bool is_sparse() const = 0;
	/** After a successful factorize: A⁻¹ on the pattern of the sparse factor (selected_inverse.h), in
	 * one pass instead of one solve per wanted column; nullptr when solving `columns` columns is the
	 * cheaper way (few columns, a dense factor), and always from the dense back end. */
	virtual std::unique_ptr<SelectedInverse> selected_inverse(int columns) const = 0;

	/** Dense LLT of the assembled matrix. */
	static std::unique_ptr<BlockCholesky> dense(const BlockPattern& pattern);
	/** CHOLMOD supernodal LLT with the fill-reducing ordering computed once for the pattern. */
	static std::unique_ptr<BlockCholesky> sparse(const BlockPattern& pattern);
};
}  // namespace swba
