#include <swba/linear/block_cholesky.h>

#include <Eigen/CholmodSupport>
#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <stdexcept>

namespace swba
{
std::vector<int> BlockPattern::offsets() const
{
	std::vector<int> off(block_sizes.size() + 1, 0);
	for (size_t i = 0; i < block_sizes.size(); i++) off[i + 1] = off[i] + block_sizes[i];
	return off;
}

int BlockPattern::dim() const { return offsets().back(); }

namespace
{
/** What both back ends keep: the pattern and the block offsets (offsets_.back() = dimension). */
class PatternedCholesky : public BlockCholesky
{
   protected:
	explicit PatternedCholesky(const BlockPattern& p) : pattern_(p), offsets_(p.offsets()) {}
	BlockPattern pattern_;
	std::vector<int> offsets_;
};

/** Calls f(R, C) for each entry R <= C of the pattern's upper triangle, block by block and row by row
 * within a block: the order factorize() reads the blocks' entries in. */
template <class F>
void for_each_upper_entry(const BlockPattern& p, const std::vector<int>& offsets, F f)
{
	for (const auto& [i, j] : p.upper_blocks)
		for (int r = 0; r < p.block_sizes[i]; r++)
			for (int c = 0; c < p.block_sizes[j]; c++)
			{
				const int R = offsets[i] + r, C = offsets[j] + c;
				if (R <= C) f(R, C);
			}
}

class DenseBlockCholesky final : public PatternedCholesky
{
   public:
	explicit DenseBlockCholesky(const BlockPattern& p) : PatternedCholesky(p)
	{
		A_.setZero(offsets_.back(), offsets_.back());
	}
	bool factorize(const std::vector<const double*>& blocks) override
	{
		for (size_t k = 0; k < pattern_.upper_blocks.size(); k++)
		{
			const auto [i, j] = pattern_.upper_blocks[k];
			const int ni = pattern_.block_sizes[i], nj = pattern_.block_sizes[j];
			A_.block(offsets_[i], offsets_[j], ni, nj) =
				Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
					blocks[k], ni, nj);
		}
		llt_.compute(A_);  // LLT<…, Upper> reads the upper triangle only (the lower one is never written)
		return llt_.info() == Eigen::Success;
	}
	void solve(double* b) const override
	{
		Eigen::Map<Eigen::VectorXd> v(b, offsets_.back());
		v = llt_.solve(v);
	}
	void solve_columns(double* B, int ncols) const override
	{
		Eigen::Map<Eigen::MatrixXd> X(B, offsets_.back(), ncols);
		llt_.solveInPlace(X);
	}
	bool is_sparse() const override { return false; }
	std::unique_ptr<SelectedInverse> selected_inverse(int) const override { return nullptr; }

   private:
	Eigen::MatrixXd A_;
	Eigen::LLT<Eigen::MatrixXd, Eigen::Upper> llt_;
};

/** Time of one multiply-add of the selected inverse's scalar recurrence in units of one of the
 * supernodal solves' (BLAS) multiply-adds: ≈ 3 from the timings on a near-dense reduced system of 3594
 * unknowns (1.14 s against 2.2 s for the solves of every column; doc/benchmarks/run.md). */
constexpr double kTakahashiOpCost = 3.0;

/** Eigen's supernodal CHOLMOD solver with its factor readable (Eigen keeps it protected). */
class SupernodalLLT : public Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Upper>
{
   public:
	const cholmod_factor* factor() const { return m_cholmodFactor; }
};

class SparseBlockCholesky final : public PatternedCholesky
{
   public:
	explicit SparseBlockCholesky(const BlockPattern& p) : PatternedCholesky(p)
	{
		const int n = offsets_.back();
		// Upper-triangular CSC pattern; remember where each block entry lands in valuePtr().
		std::vector<Eigen::Triplet<double>> trip;
		for_each_upper_entry(pattern_, offsets_, [&](int R, int C) { trip.emplace_back(R, C, 1.0); });
		A_.resize(n, n);
		A_.setFromTriplets(trip.begin(), trip.end());
		A_.makeCompressed();
		value_index_.reserve(trip.size());
		for_each_upper_entry(pattern_, offsets_, [&](int R, int C) {
			const int* begin = A_.innerIndexPtr() + A_.outerIndexPtr()[C];
			const int* end = A_.innerIndexPtr() + A_.outerIndexPtr()[C + 1];
			const int* it = std::lower_bound(begin, end, R);
			value_index_.push_back(static_cast<int>(it - A_.innerIndexPtr()));
		});
		solver_.analyzePattern(A_);
		if (solver_.info() != Eigen::Success)
			throw std::runtime_error("CHOLMOD: symbolic analysis failed");
	}
	bool factorize(const std::vector<const double*>& blocks) override
	{
		double* vals = A_.valuePtr();
		size_t q = 0;
		for (size_t k = 0; k < pattern_.upper_blocks.size(); k++)
		{
			const auto [i, j] = pattern_.upper_blocks[k];
			const int ni = pattern_.block_sizes[i], nj = pattern_.block_sizes[j];
			const double* B = blocks[k];
			for (int r = 0; r < ni; r++)
				for (int c = 0; c < nj; c++)
				{
					if (i == j && r > c) continue;
					vals[value_index_[q++]] = B[r * nj + c];
				}
		}
		solver_.factorize(A_);
		return solver_.info() == Eigen::Success;
	}
	void solve(double* b) const override
	{
		Eigen::Map<Eigen::VectorXd> v(b, offsets_.back());
		Eigen::VectorXd x = solver_.solve(v);
		v = x;
	}
	void solve_columns(double* B, int ncols) const override
	{
		Eigen::Map<Eigen::MatrixXd> M(B, offsets_.back(), ncols);
		Eigen::MatrixXd X = solver_.solve(M);
		M = X;
	}
	bool is_sparse() const override { return true; }
	std::unique_ptr<SelectedInverse> selected_inverse(int columns) const override
	{
		// A simplicial LLᵀ copy of the supernodal factor: compressed columns, rows sorted, diagonal first.
		cholmod_common& cm = solver_.cholmod();
		auto free_factor = [&cm](cholmod_factor* f) { cholmod_free_factor(&f, &cm); };
		std::unique_ptr<cholmod_factor, decltype(free_factor)> L(
			cholmod_copy_factor(const_cast<cholmod_factor*>(solver_.factor()), &cm), free_factor);
		if (!L || !cholmod_change_factor(CHOLMOD_REAL, 1, 0, 1, 1, L.get(), &cm))
			return nullptr;  // out of memory for the copy: the solves need none
		const int n = static_cast<int>(L->n);
		const int* p = static_cast<const int*>(L->p);
		const double solve_work = 2.0 * columns * p[n];
		if (kTakahashiOpCost * SelectedInverse::work(n, p, static_cast<const int*>(L->i)) > solve_work) return nullptr;
		return std::make_unique<SelectedInverse>(static_cast<int>(L->n), static_cast<const int*>(L->p),
												 static_cast<const int*>(L->i), static_cast<const double*>(L->x),
												 static_cast<const int*>(L->Perm));
	}

   private:
	Eigen::SparseMatrix<double> A_;
	std::vector<int> value_index_;
	mutable SupernodalLLT solver_;
};
}  // namespace

std::unique_ptr<BlockCholesky> BlockCholesky::dense(const BlockPattern& pattern)
{
	return std::make_unique<DenseBlockCholesky>(pattern);
}

std::unique_ptr<BlockCholesky> BlockCholesky::sparse(const BlockPattern& pattern)
{
	return std::make_unique<SparseBlockCholesky>(pattern);
}
}  // namespace swba
