#include "normal_equations.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <map>
#include <stdexcept>
#include <string>

#include "small_blocks.h"

namespace swba::detail
{
// Below this many items a loop runs on one thread: thread start-up and barriers cost more.
constexpr int kParallelMin = 2000;

namespace
{
/** (i, j) → block index, −1 if absent: a dense table while rows·cols is small (a window's system,
 * rebuilt every step), an ordered map otherwise (BAL: thousands of cameras). */
class BlockIndex
{
   public:
	BlockIndex(int rows, int cols) : cols_(cols)
	{
		if (static_cast<long long>(rows) * cols <= kDenseMaxEntries)
			dense_.assign(static_cast<size_t>(rows) * static_cast<size_t>(cols), -1);
	}
	int find(int i, int j) const
	{
		if (!dense_.empty()) return dense_[static_cast<size_t>(i) * cols_ + j];
		const auto it = map_.find({i, j});
		return it == map_.end() ? -1 : it->second;
	}
	void set(int i, int j, int index)
	{
		if (!dense_.empty())
			dense_[static_cast<size_t>(i) * cols_ + j] = index;
		else
			map_[{i, j}] = index;
	}

   private:
	static constexpr long long kDenseMaxEntries = 1 << 20;
	size_t cols_;
	std::vector<int> dense_;
	std::map<std::pair<int, int>, int> map_;
};
}  // namespace

std::set<VariableId> linked_eliminable_variables(const Problem& problem)
{
	std::set<VariableId> linked;
	std::vector<VariableId> elim;
	for (const auto& [fid, fe] : problem.factors())
	{
		elim.clear();
		for (VariableId v : fe.variables)
		{
			const auto& var = problem.variables().at(v);
			if (!var.constant && var.group == Group::Eliminable) elim.push_back(v);
		}
		if (elim.size() > 1) linked.insert(elim.begin(), elim.end());
	}
	return linked;
}

NormalEquations::NormalEquations(Problem& problem, bool use_schur, bool sparse, int num_threads,
								 const std::set<VariableId>& keep)
	: problem_(problem), use_schur_(use_schur), sparse_(sparse), num_threads_(std::max(1, num_threads))
{
	// Ordering: kept variables first (by id), then eliminated ones (by id); constants removed.
	std::map<VariableId, std::pair<int, int>> where;  // id -> (kind, index)
	for (auto& [id, cv] : problem_.variables())
	{
		auto& v = const_cast<Problem::Variable&>(cv);
		if (v.constant)
		{
			num_constant_++;
			where[id] = {2, -1};
			continue;
		}
		const int t = v.manifold->tangent_size();
		if (use_schur_ && v.group == Group::Eliminable && keep.count(id) == 0)
		{
			where[id] = {1, static_cast<int>(elim_.size())};
			elim_.push_back({id, &v, t, elim_dim_});
			elim_dim_ += t;
		}
		else
		{
			where[id] = {0, static_cast<int>(kept_.size())};
			kept_.push_back({id, &v, t, kept_dim_});
			kept_dim_ += t;
		}
	}
	var_factors_kept_.resize(kept_.size());
	var_factors_elim_.resize(elim_.size());
	int roff = 0, joff = 0;
	for (const auto& [fid, fe] : problem_.factors())
	{
		FactorSlotInfo fs;
		fs.factor = fe.factor.get();
		fs.loss = fe.loss.get();
		fs.m = fe.factor->residual_dim();
		fs.residual_offset = roff;
		roff += fs.m;
		int n_elim = 0;
		const int fidx = static_cast<int>(factors_.size());
		for (size_t s = 0; s < fe.variables.size(); s++)
		{
			const auto [kind, index] = where.at(fe.variables[s]);
			fs.values.push_back(problem_.value(fe.variables[s]));
			fs.kind.push_back(kind);
			fs.index.push_back(index);
			if (kind == 2)
			{
				fs.jacobian_offset.push_back(-1);
				continue;
			}
			fs.jacobian_offset.push_back(joff);
			joff += fs.m * fe.factor->tangent_dims()[s];
			if (kind == 1)
			{
				n_elim++;
				var_factors_elim_[index].push_back({fidx, static_cast<int>(s)});
			}
			else
				var_factors_kept_[index].push_back({fidx, static_cast<int>(s)});
		}
		if (n_elim > 1)
			throw std::invalid_argument("solve: factor " + std::to_string(fid) +
										" connects two eliminable variables; Schur elimination needs "
										"landmarks that only connect to kept variables");
		factors_.push_back(std::move(fs));
	}
	residuals_.assign(roff, 0.0);
	jacobians_.assign(joff, 0.0);
	valid_.assign(factors_.size(), 1);
	factor_cost_.assign(factors_.size(), 0.0);
	build_patterns();
}

void NormalEquations::build_patterns()
{
	const int nk = num_kept(), ne = num_elim();
	// H_pp blocks.
	BlockIndex pp_index(nk, nk);
	auto pp_block = [&](int a, int b) {
		const int i = std::min(a, b), j = std::max(a, b);
		int idx = pp_index.find(i, j);
		if (idx >= 0) return idx;
		idx = static_cast<int>(pp_blocks_.size());
		pp_index.set(i, j, idx);
		pp_blocks_.emplace_back(i, j);
		pp_contrib_.emplace_back();
		return idx;
	};
	pp_diag_block_.resize(kept_.size());
	for (int a = 0; a < nk; a++) pp_diag_block_[a] = pp_block(a, a);
	BlockIndex pl_index(nk, ne);
	for (int f = 0; f < num_factors(); f++)
	{
		const auto& fs = factors_[f];
		const int k = static_cast<int>(fs.kind.size());
		for (int s = 0; s < k; s++)
		{
			if (fs.kind[s] != 0) continue;
			for (int t = 0; t < k; t++)
			{
				if (fs.kind[t] == 0 && fs.index[s] <= fs.index[t])
					pp_contrib_[pp_block(fs.index[s], fs.index[t])].push_back({f, s, t});
				else if (fs.kind[t] == 1)
				{
					int idx = pl_index.find(fs.index[s], fs.index[t]);
					if (idx < 0)
					{
						idx = static_cast<int>(pl_blocks_.size());
						pl_index.set(fs.index[s], fs.index[t], idx);
						pl_blocks_.push_back({fs.index[s], fs.index[t], 0, {}});
					}
					pl_blocks_[idx].contrib.push_back({f, s, t});
				}
			}
		}
	}
	// Deterministic block order: sort pp blocks by (i, j).
	{
		std::vector<int> perm(pp_blocks_.size());
		for (size_t i = 0; i < perm.size(); i++) perm[i] = static_cast<int>(i);
		std::sort(perm.begin(), perm.end(), [&](int x, int y) { return pp_blocks_[x] < pp_blocks_[y]; });
		std::vector<std::pair<int, int>> blocks;
		std::vector<std::vector<Contribution>> contrib;
		std::vector<int> inv(perm.size());
		for (size_t i = 0; i < perm.size(); i++)
		{
			blocks.push_back(pp_blocks_[perm[i]]);
			contrib.push_back(std::move(pp_contrib_[perm[i]]));
			inv[perm[i]] = static_cast<int>(i);
		}
		pp_blocks_ = std::move(blocks);
		pp_contrib_ = std::move(contrib);
		for (auto& d : pp_diag_block_) d = inv[d];
		for (size_t i = 0; i < pp_blocks_.size(); i++)
			pp_index.set(pp_blocks_[i].first, pp_blocks_[i].second, static_cast<int>(i));
	}
	pp_offset_.resize(pp_blocks_.size());
	int off = 0;
	for (size_t i = 0; i < pp_blocks_.size(); i++)
	{
		pp_offset_[i] = off;
		off += kept_[pp_blocks_[i].first].tangent * kept_[pp_blocks_[i].second].tangent;
	}
	Hpp_.assign(off, 0.0);

	// H_pl blocks, sorted by (elim, kept) so that each landmark's blocks are contiguous.
	std::sort(pl_blocks_.begin(), pl_blocks_.end(), [](const PlBlock& x, const PlBlock& y) {
		return std::make_pair(x.elim, x.kept) < std::make_pair(y.elim, y.kept);
	});
	elim_pl_.assign(elim_.size(), {});
	kept_pl_.assign(kept_.size(), {});
	off = 0;
	for (size_t i = 0; i < pl_blocks_.size(); i++)
	{
		auto& pb = pl_blocks_[i];
		pb.offset = off;
		off += kept_[pb.kept].tangent * elim_[pb.elim].tangent;
		elim_pl_[pb.elim].push_back(static_cast<int>(i));
		kept_pl_[pb.kept].push_back(static_cast<int>(i));
	}
	Hlp_.assign(off, 0.0);
	ll_offset_.resize(elim_.size());
	off = 0;
	for (size_t l = 0; l < elim_.size(); l++)
	{
		ll_offset_[l] = off;
		off += elim_[l].tangent * elim_[l].tangent;
	}
	Hll_.assign(off, 0.0);
	Hll_inv_.assign(off, 0.0);
	g_.assign(kept_dim_ + elim_dim_, 0.0);

	// Reduced system pattern: H_pp blocks ∪ pairs of kept variables sharing an eliminated one, sorted.
	std::vector<std::pair<int, int>> s_keys(pp_blocks_);
	for (size_t l = 0; l < elim_.size(); l++)
	{
		const auto& list = elim_pl_[l];
		// list is sorted by kept index, so pl_blocks_[list[x]].kept ≤ pl_blocks_[list[y]].kept for x ≤ y.
		for (size_t x = 0; x < list.size(); x++)
			for (size_t y = x; y < list.size(); y++)
				s_keys.emplace_back(pl_blocks_[list[x]].kept, pl_blocks_[list[y]].kept);
	}
	std::sort(s_keys.begin(), s_keys.end());
	s_keys.erase(std::unique(s_keys.begin(), s_keys.end()), s_keys.end());
	BlockIndex s_index(nk, nk);
	s_pattern_.block_sizes.clear();
	for (const auto& v : kept_) s_pattern_.block_sizes.push_back(v.tangent);
	s_pattern_.upper_blocks.clear();
	s_pp_block_.clear();
	s_offset_.clear();
	s_row_begin_.assign(kept_.size() + 1, 0);
	off = 0;
	for (const auto& key : s_keys)
	{
		const int index = static_cast<int>(s_pattern_.upper_blocks.size());
		s_index.set(key.first, key.second, index);
		s_pattern_.upper_blocks.push_back(key);
		s_pp_block_.push_back(pp_index.find(key.first, key.second));
		s_offset_.push_back(off);
		off += kept_[key.first].tangent * kept_[key.second].tangent;
		s_row_begin_[key.first + 1] = index + 1;
	}
	// Every kept variable has its diagonal block, so every row is non-empty and the ends are set.
	S_.assign(off, 0.0);
	s_block_ptr_.resize(s_offset_.size());
	for (size_t k = 0; k < s_offset_.size(); k++) s_block_ptr_[k] = S_.data() + s_offset_[k];
	// Schur terms per pl block (a, l): the S offsets of (a, b) for the pl blocks (b, l) with b ≥ a.
	pl_pos_.assign(pl_blocks_.size(), 0);
	pl_term_begin_.assign(pl_blocks_.size(), 0);
	term_s_offset_.clear();
	for (size_t l = 0; l < elim_.size(); l++)
	{
		const auto& list = elim_pl_[l];
		for (size_t x = 0; x < list.size(); x++)
		{
			pl_pos_[list[x]] = static_cast<int>(x);
			pl_term_begin_[list[x]] = static_cast<int>(term_s_offset_.size());
			for (size_t y = x; y < list.size(); y++)
				term_s_offset_.push_back(
					s_offset_[s_index.find(pl_blocks_[list[x]].kept, pl_blocks_[list[y]].kept)]);
		}
	}
	uniform_kept_ = kept_.empty() ? 0 : kept_[0].tangent;
	for (const auto& v : kept_)
		if (v.tangent != uniform_kept_) uniform_kept_ = 0;
	uniform_elim_ = elim_.empty() ? 0 : elim_[0].tangent;
	for (const auto& v : elim_)
		if (v.tangent != uniform_elim_) uniform_elim_ = 0;
	rhs_.setZero(kept_dim_);
}

void NormalEquations::set_sparse(bool sparse)
{
	if (sparse != sparse_) cholesky_.reset();
	sparse_ = sparse;
}

double NormalEquations::reduced_block_fill() const
{
	const double n = static_cast<double>(kept_.size());
	return n > 0 ? static_cast<double>(s_pattern_.upper_blocks.size()) / (n * (n + 1) / 2) : 1.0;
}

void NormalEquations::ensure_cholesky()
{
	if (!cholesky_ && kept_dim_ > 0)
		cholesky_ = sparse_ ? BlockCholesky::sparse(s_pattern_) : BlockCholesky::dense(s_pattern_);
}

double NormalEquations::evaluate(bool want_jacobians, int* dropped, int* newly_dropped)
{
	const int nf = num_factors();
	if (newly_dropped) valid_before_ = valid_;
#pragma omp parallel for schedule(dynamic, 256) num_threads(num_threads_) if (nf > kParallelMin)
	for (int f = 0; f < nf; f++)
	{
		const auto& fs = factors_[f];
		const int k = static_cast<int>(fs.values.size());
		double* r = residuals_.data() + fs.residual_offset;
		double* jac[16];
		int cols[16];
		std::vector<double*> jac_heap;
		double** J = jac;
		int* C = cols;
		std::vector<int> cols_heap;
		if (k > 16)
		{
			jac_heap.resize(k);
			cols_heap.resize(k);
			J = jac_heap.data();
			C = cols_heap.data();
		}
		for (int s = 0; s < k; s++)
		{
			J[s] = (want_jacobians && fs.jacobian_offset[s] >= 0) ? jacobians_.data() + fs.jacobian_offset[s]
																  : nullptr;
			C[s] = fs.factor->tangent_dims()[s];
		}
		const bool ok = fs.factor->evaluate_whitened(fs.values.data(), r, want_jacobians ? J : nullptr);
		bool finite = ok;
		if (ok)
			for (int i = 0; i < fs.m; i++) finite = finite && std::isfinite(r[i]);
		if (!finite)
		{
			valid_[f] = 0;
			factor_cost_[f] = 0;
			std::fill(r, r + fs.m, 0.0);
			if (want_jacobians)
				for (int s = 0; s < k; s++)
					if (J[s]) std::fill(J[s], J[s] + fs.m * C[s], 0.0);
			continue;
		}
		valid_[f] = 1;
		if (fs.loss)
			factor_cost_[f] = apply_loss(*fs.loss, fs.m, r, k, C, want_jacobians ? J : nullptr);
		else
		{
			double s2 = 0;
			for (int i = 0; i < fs.m; i++) s2 += r[i] * r[i];
			factor_cost_[f] = 0.5 * s2;
		}
	}
	double cost = 0;
	int nd = 0;
	for (int f = 0; f < nf; f++)
	{
		cost += factor_cost_[f];
		nd += valid_[f] ? 0 : 1;
	}
	if (dropped) *dropped = nd;
	if (newly_dropped)
	{
		*newly_dropped = 0;
		for (int f = 0; f < nf; f++) *newly_dropped += (valid_before_[f] && !valid_[f]) ? 1 : 0;
	}
	return cost;
}

void NormalEquations::assemble()
{
	auto jac = [&](int f, int s) { return jacobians_.data() + factors_[f].jacobian_offset[s]; };
	auto tdim = [&](int f, int s) { return factors_[f].factor->tangent_dims()[s]; };
	const int npp = static_cast<int>(pp_blocks_.size());
#pragma omp parallel num_threads(num_threads_) if (num_factors() > kParallelMin)
	{
#pragma omp for schedule(dynamic, 64) nowait
		for (int b = 0; b < npp; b++)
		{
			const int na = kept_[pp_blocks_[b].first].tangent, nb = kept_[pp_blocks_[b].second].tangent;
			double* H = Hpp_.data() + pp_offset_[b];
			std::fill(H, H + na * nb, 0.0);
			for (const auto& c : pp_contrib_[b])
			{
				if (!valid_[c.factor]) continue;
				add_AtB(jac(c.factor, c.slot_a), jac(c.factor, c.slot_b), factors_[c.factor].m, na, nb, H);
			}
		}
		const int npl = static_cast<int>(pl_blocks_.size());
#pragma omp for schedule(dynamic, 256) nowait
		for (int b = 0; b < npl; b++)
		{
			const auto& pb = pl_blocks_[b];
			const int na = kept_[pb.kept].tangent, nl = elim_[pb.elim].tangent;
			double* H = Hlp_.data() + pb.offset;  // H_lp = Σ J_lᵀ J_p (nl × na)
			std::fill(H, H + na * nl, 0.0);
			for (const auto& c : pb.contrib)
			{
				if (!valid_[c.factor]) continue;
				add_AtB(jac(c.factor, c.slot_b), jac(c.factor, c.slot_a), factors_[c.factor].m, nl, na, H);
			}
		}
		const int ne = num_elim();
#pragma omp for schedule(dynamic, 256) nowait
		for (int l = 0; l < ne; l++)
		{
			const int nl = elim_[l].tangent;
			double* H = Hll_.data() + ll_offset_[l];
			double* g = g_.data() + kept_dim_ + elim_[l].offset;
			std::fill(H, H + nl * nl, 0.0);
			std::fill(g, g + nl, 0.0);
			for (const auto& [f, s] : var_factors_elim_[l])
			{
				if (!valid_[f]) continue;
				add_AtB(jac(f, s), jac(f, s), factors_[f].m, nl, nl, H);
				add_Atr(jac(f, s), residuals_.data() + factors_[f].residual_offset, factors_[f].m, nl, g);
			}
		}
		const int nk = num_kept();
#pragma omp for schedule(dynamic, 64)
		for (int a = 0; a < nk; a++)
		{
			const int na = kept_[a].tangent;
			double* g = g_.data() + kept_[a].offset;
			std::fill(g, g + na, 0.0);
			for (const auto& [f, s] : var_factors_kept_[a])
			{
				if (!valid_[f]) continue;
				add_Atr(jac(f, s), residuals_.data() + factors_[f].residual_offset, factors_[f].m, tdim(f, s), g);
			}
		}
	}
}

double NormalEquations::gradient_max_norm() const
{
	double m = 0;
	for (double v : g_) m = std::max(m, std::abs(v));
	return m;
}

namespace
{
double damped(double d, double lambda, double min_diag, double max_diag)
{
	return lambda * std::clamp(d, min_diag, max_diag);
}

/** Calls f(integral_constant NP, integral_constant NL) for the uniform block sizes of BAL (9, 3),
 * pose + point (6, 3) and planar (3, 2 / 3, 3) problems, and for mixed kept sizes with 3-dimensional
 * eliminated variables (NP dynamic, dispatched per block); anything else runs with run-time sizes. */
template <typename F>
void dispatch_schur_sizes(int np, int nl, F&& f)
{
	using Dyn = std::integral_constant<int, Eigen::Dynamic>;
	if (np == 9 && nl == 3)
		f(std::integral_constant<int, 9>(), std::integral_constant<int, 3>());
	else if (np == 6 && nl == 3)
		f(std::integral_constant<int, 6>(), std::integral_constant<int, 3>());
	else if (np == 6 && nl == 1)
		f(std::integral_constant<int, 6>(), std::integral_constant<int, 1>());
	else if (np == 3 && nl == 2)
		f(std::integral_constant<int, 3>(), std::integral_constant<int, 2>());
	else if (nl == 3)  // poses and landmarks kept together (a window's prior), points eliminated
		f(Dyn(), std::integral_constant<int, 3>());
	else
		f(Dyn(), Dyn());
}
}  // namespace

/** S (na×nb) −= W (na×nl) · H (nl×nb), row-major; S[i][j] −= Σ_k W[i][k] H[k][j] with the sum formed
 * first (in k order). Written row by row over j (contiguous in H and S) so that the compiler
 * vectorises across j; the pointers never alias. */
template <int NA, int NB, int NL>
inline void sub_WH(const double* __restrict W, const double* __restrict H, int na_, int nb_, int nl_,
				   double* __restrict S)
{
	const int na = dim_or<NA>(na_), nb = dim_or<NB>(nb_), nl = dim_or<NL>(nl_);
	if constexpr (NB > 0)
	{
		for (int i = 0; i < na; i++)
		{
			double t[NB];
			const double w0 = W[i * nl];
			for (int j = 0; j < NB; j++) t[j] = w0 * H[j];
			for (int k = 1; k < nl; k++)
			{
				const double w = W[i * nl + k];
				for (int j = 0; j < NB; j++) t[j] += w * H[k * NB + j];
			}
			for (int j = 0; j < NB; j++) S[i * NB + j] -= t[j];
		}
	}
	else
	{
		for (int i = 0; i < na; i++)
			for (int j = 0; j < nb; j++)
			{
				double acc = W[i * nl] * H[j];
				for (int k = 1; k < nl; k++) acc += W[i * nl + k] * H[k * nb + j];
				S[i * nb + j] -= acc;
			}
	}
}

/** Upper triangle (j ≥ i) of S (n×n) −= W (n×nl) · H (nl×n), for a diagonal block of S (H = Wᵀ up to
 * H_ll⁻¹; the lower triangle is mirrored once the block row is complete). */
template <int N, int NL>
inline void sub_WH_upper(const double* __restrict W, const double* __restrict H, int n_, int nl_,
						 double* __restrict S)
{
	const int n = dim_or<N>(n_), nl = dim_or<NL>(nl_);
	for (int i = 0; i < n; i++)
		for (int j = i; j < n; j++)
		{
			double acc = W[i * nl] * H[j];
			for (int k = 1; k < nl; k++) acc += W[i * nl + k] * H[k * n + j];
			S[i * n + j] -= acc;
		}
}

/** sub_WH / sub_WH_upper for a kept block size known only at run time: compiled kernels for the
 * pose (6) and point (3) sizes, the generic loop otherwise. */
template <int NL>
inline void sub_WH_mixed(const double* W, const double* H, int na, int nb, int nl, double* S)
{
	if (na == 6 && nb == 6)
		sub_WH<6, 6, NL>(W, H, na, nb, nl, S);
	else if (na == 6 && nb == 3)
		sub_WH<6, 3, NL>(W, H, na, nb, nl, S);
	else if (na == 3 && nb == 6)
		sub_WH<3, 6, NL>(W, H, na, nb, nl, S);
	else if (na == 3 && nb == 3)
		sub_WH<3, 3, NL>(W, H, na, nb, nl, S);
	else
		sub_WH<Eigen::Dynamic, Eigen::Dynamic, NL>(W, H, na, nb, nl, S);
}

template <int NL>
inline void sub_WH_upper_mixed(const double* W, const double* H, int n, int nl, double* S)
{
	if (n == 6)
		sub_WH_upper<6, NL>(W, H, n, nl, S);
	else if (n == 3)
		sub_WH_upper<3, NL>(W, H, n, nl, S);
	else
		sub_WH_upper<Eigen::Dynamic, NL>(W, H, n, nl, S);
}

template <int NL>
bool NormalEquations::invert_damped_ll(int l, double lambda, double min_diag, double max_diag)
{
	const int nl = dim_or<NL>(elim_[l].tangent);
	using Mat = Eigen::Matrix<double, NL, NL, NL == 1 ? Eigen::ColMajor : Eigen::RowMajor>;
	Eigen::Map<const Mat> H(Hll_.data() + ll_offset_[l], nl, nl);
	Eigen::Map<Mat> Hinv(Hll_inv_.data() + ll_offset_[l], nl, nl);
	Mat Hd = H;
	for (int i = 0; i < nl; i++) Hd(i, i) += damped(H(i, i), lambda, min_diag, max_diag);
	Eigen::LLT<Mat> llt(Hd);
	if (llt.info() != Eigen::Success)
	{
		Hinv.setZero();
		return false;
	}
	Hinv = llt.solve(Mat::Identity(nl, nl));
	return true;
}

template <int NP, int NL>
void NormalEquations::schur_row(int a, double lambda, double min_diag, double max_diag, double* rhs)
{
	const int na = dim_or<NP>(kept_[a].tangent);
	// S_ab ← H_ab (+ λD on the diagonal block), zero for blocks that only come from the elimination.
	for (int k = s_row_begin_[a]; k < s_row_begin_[a + 1]; k++)
	{
		const int b = s_pattern_.upper_blocks[k].second;
		const int nb = dim_or<NP>(kept_[b].tangent);
		double* S = S_.data() + s_offset_[k];
		if (s_pp_block_[k] >= 0)
			std::copy_n(Hpp_.data() + pp_offset_[s_pp_block_[k]], na * nb, S);
		else
			std::fill(S, S + na * nb, 0.0);
		if (a == b)
			for (int i = 0; i < na; i++) S[i * na + i] += damped(S[i * na + i], lambda, min_diag, max_diag);
	}
	double* r = rhs + kept_[a].offset;
	for (int i = 0; i < na; i++) r[i] = -g_[kept_[a].offset + i];
	constexpr bool fixed = NP > 0 && NL > 0;
	double W_fixed[fixed ? NP * NL : 1];
	std::vector<double> W_dynamic;
	for (const int pa : kept_pl_[a])
	{
		const auto& pb = pl_blocks_[pa];
		const int l = pb.elim;
		const int nl = dim_or<NL>(elim_[l].tangent);
		double* W = W_fixed;
		if constexpr (!fixed)
		{
			W_dynamic.resize(static_cast<size_t>(na) * nl);
			W = W_dynamic.data();
		}
		// W = H_al H_ll⁻¹ = H_laᵀ H_ll⁻¹ (na × nl).
		const double* Hla = Hlp_.data() + pb.offset;
		const double* Hinv = Hll_inv_.data() + ll_offset_[l];
		for (int i = 0; i < na; i++)
			for (int k = 0; k < nl; k++)
			{
				double acc = Hla[i] * Hinv[k];
				for (int m = 1; m < nl; m++) acc += Hla[m * na + i] * Hinv[m * nl + k];
				W[i * nl + k] = acc;
			}
		// rhs_a += W g_l.
		const double* gl = g_.data() + kept_dim_ + elim_[l].offset;
		for (int i = 0; i < na; i++)
		{
			double acc = W[i * nl] * gl[0];
			for (int k = 1; k < nl; k++) acc += W[i * nl + k] * gl[k];
			r[i] += acc;
		}
		// S_ab −= W H_lb for the blocks (b ≥ a, l).
		const auto& list = elim_pl_[l];
		const int* s_off = term_s_offset_.data() + pl_term_begin_[pa];
		// The first block is (a, l) itself: the diagonal block S_aa, upper triangle only.
		if constexpr (NP > 0)
			sub_WH_upper<NP, NL>(W, Hla, na, nl, S_.data() + *s_off);
		else
			sub_WH_upper_mixed<NL>(W, Hla, na, nl, S_.data() + *s_off);
		s_off++;
		for (size_t y = static_cast<size_t>(pl_pos_[pa]) + 1; y < list.size(); y++, s_off++)
		{
			const auto& pbb = pl_blocks_[list[y]];
			const int nb = dim_or<NP>(kept_[pbb.kept].tangent);
			const double* Hlb = Hlp_.data() + pbb.offset;
			if constexpr (NP > 0)
				sub_WH<NP, NP, NL>(W, Hlb, na, nb, nl, S_.data() + *s_off);
			else
				sub_WH_mixed<NL>(W, Hlb, na, nb, nl, S_.data() + *s_off);
		}
	}
	// Mirror the diagonal block's upper triangle (the back ends read full diagonal blocks).
	double* Saa = S_.data() + s_offset_[s_row_begin_[a]];
	for (int i = 0; i < na; i++)
		for (int j = 0; j < i; j++) Saa[i * na + j] = Saa[j * na + i];
}

template <int NP, int NL>
void NormalEquations::back_substitute(int l, double* delta) const
{
	const int nl = dim_or<NL>(elim_[l].tangent);
	constexpr bool fixed = NL > 0;
	double v_fixed[fixed ? NL : 1];
	std::vector<double> v_dynamic;
	double* v = v_fixed;
	if constexpr (!fixed)
	{
		v_dynamic.resize(nl);
		v = v_dynamic.data();
	}
	const double* gl = g_.data() + kept_dim_ + elim_[l].offset;
	for (int k = 0; k < nl; k++) v[k] = -gl[k];
	for (const int pb_index : elim_pl_[l])
	{
		const auto& pb = pl_blocks_[pb_index];
		const int nb = dim_or<NP>(kept_[pb.kept].tangent);
		const double* H = Hlp_.data() + pb.offset;
		const double* dp = delta + kept_[pb.kept].offset;
		for (int k = 0; k < nl; k++)
		{
			double acc = H[k * nb] * dp[0];
			for (int j = 1; j < nb; j++) acc += H[k * nb + j] * dp[j];
			v[k] -= acc;
		}
	}
	const double* Hinv = Hll_inv_.data() + ll_offset_[l];
	double* dl = delta + kept_dim_ + elim_[l].offset;
	for (int i = 0; i < nl; i++)
	{
		double acc = Hinv[i * nl] * v[0];
		for (int k = 1; k < nl; k++) acc += Hinv[i * nl + k] * v[k];
		dl[i] = acc;
	}
}

bool NormalEquations::solve_damped(double lambda, double min_diag, double max_diag, Eigen::VectorXd& delta)
{
	delta.setZero(kept_dim_ + elim_dim_);
	const int ne = num_elim(), nk = num_kept();
	const int num_terms = static_cast<int>(term_s_offset_.size());
	const bool parallel = num_threads_ > 1 && (ne > kParallelMin || num_terms > kParallelMin || nk > kParallelMin);
	int failed = 0;
	// One parallel region: 1. damped H_ll⁻¹ per eliminated variable; 2. the reduced system
	// S = H_pp + λD − Σ_l H_pl H_ll⁻¹ H_lp and rhs = −g_p + Σ_l H_pl H_ll⁻¹ g_l, block row by block row.
	dispatch_schur_sizes(uniform_kept_, uniform_elim_, [&](auto NPc, auto NLc) {
		constexpr int NP = decltype(NPc)::value, NL = decltype(NLc)::value;
#pragma omp parallel num_threads(num_threads_) if (parallel)
		{
#pragma omp for schedule(dynamic, 256) reduction(+ : failed)
			for (int l = 0; l < ne; l++) failed += invert_damped_ll<NL>(l, lambda, min_diag, max_diag) ? 0 : 1;
#pragma omp for schedule(dynamic, 1)
			for (int a = 0; a < nk; a++) schur_row<NP, NL>(a, lambda, min_diag, max_diag, rhs_.data());
		}
	});
	if (failed > 0) return false;
	if (kept_dim_ > 0)
	{
		ensure_cholesky();
		if (!cholesky_->factorize(s_block_ptr_)) return false;
		cholesky_->solve(rhs_.data());
		if (!rhs_.allFinite()) return false;
		delta.head(kept_dim_) = rhs_;
	}
	// 3. Back-substitution: δ_l = H_ll⁻¹ (−g_l − Σ H_lp δ_p).
	dispatch_schur_sizes(uniform_kept_, uniform_elim_, [&](auto NPc, auto NLc) {
		constexpr int NP = decltype(NPc)::value, NL = decltype(NLc)::value;
#pragma omp parallel for schedule(dynamic, 256) num_threads(num_threads_) if (num_threads_ > 1 && ne > kParallelMin)
		for (int l = 0; l < ne; l++) back_substitute<NP, NL>(l, delta.data());
	});
	return delta.allFinite();
}

double NormalEquations::model_decrease(const Eigen::VectorXd& delta) const
{
	// −gᵀδ − ½ δᵀHδ with δᵀHδ summed blockwise from the undamped blocks (no H δ vector).
	const double* d = delta.data();
	double quad = 0;
	for (size_t b = 0; b < pp_blocks_.size(); b++)
	{
		const auto [i, j] = pp_blocks_[b];
		const double q = quadratic_form(d + kept_[i].offset, Hpp_.data() + pp_offset_[b], d + kept_[j].offset,
										kept_[i].tangent, kept_[j].tangent);
		quad += i == j ? q : 2 * q;
	}
	for (const auto& pb : pl_blocks_)
		quad += 2 * quadratic_form(d + kept_dim_ + elim_[pb.elim].offset, Hlp_.data() + pb.offset,
								   d + kept_[pb.kept].offset, elim_[pb.elim].tangent, kept_[pb.kept].tangent);
	for (size_t l = 0; l < elim_.size(); l++)
	{
		const double* dl = d + kept_dim_ + elim_[l].offset;
		quad += quadratic_form(dl, Hll_.data() + ll_offset_[l], dl, elim_[l].tangent, elim_[l].tangent);
	}
	Eigen::Map<const Eigen::VectorXd> g(g_.data(), g_.size());
	return -g.dot(delta) - 0.5 * quad;
}

void NormalEquations::save_values()
{
	backup_.clear();
	for (const auto* list : {&kept_, &elim_})
		for (const auto& v : *list) backup_.insert(backup_.end(), v.var->value.begin(), v.var->value.end());
}

void NormalEquations::restore_values()
{
	size_t pos = 0;
	for (auto* list : {&kept_, &elim_})
		for (auto& v : *list)
		{
			std::copy_n(backup_.data() + pos, v.var->value.size(), v.var->value.data());
			pos += v.var->value.size();
		}
}

void NormalEquations::apply_step(const Eigen::VectorXd& delta)
{
	for (auto& v : kept_) v.var->manifold->plus(v.var->value.data(), delta.data() + v.offset, v.var->value.data());
	for (auto& v : elim_)
		v.var->manifold->plus(v.var->value.data(), delta.data() + kept_dim_ + v.offset, v.var->value.data());
}

double NormalEquations::values_norm() const
{
	double s = 0;
	for (const auto* list : {&kept_, &elim_})
		for (const auto& v : *list)
			for (double x : v.var->value) s += x * x;
	return std::sqrt(s);
}
}  // namespace swba::detail
