#include "schur_eliminator.h"

#include <Eigen/Cholesky>
#include <algorithm>

#include "block_index.h"
#include "program_evaluator.h"
#include "small_blocks.h"

namespace swba::detail
{
namespace
{
using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

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
}  // namespace

SchurEliminator::SchurEliminator(const Program& program, const NormalEquations& equations, bool sparse,
								 int num_threads)
	: program_(program), ne_(equations), sparse_(sparse), num_threads_(std::max(1, num_threads))
{
	int ll_size = 0;
	for (const auto& v : program_.elim()) ll_size += v.tangent * v.tangent;
	Hll_inv_.assign(ll_size, 0.0);
	build_reduced_pattern();
	build_schur_terms();
	rhs_.setZero(program_.kept_dim());
}

void SchurEliminator::build_reduced_pattern()
{
	// H_pp blocks ∪ pairs of kept variables sharing an eliminated one, sorted.
	const auto& kept = program_.kept();
	const auto& pl = ne_.pl_blocks();
	std::vector<std::pair<int, int>> s_keys(ne_.pp_blocks());
	for (int l = 0; l < program_.num_elim(); l++)
	{
		const auto& list = ne_.elim_pl(l);
		// list is sorted by kept index, so pl[list[x]].kept ≤ pl[list[y]].kept for x ≤ y.
		for (size_t x = 0; x < list.size(); x++)
			for (size_t y = x; y < list.size(); y++) s_keys.emplace_back(pl[list[x]].kept, pl[list[y]].kept);
	}
	std::sort(s_keys.begin(), s_keys.end());
	s_keys.erase(std::unique(s_keys.begin(), s_keys.end()), s_keys.end());
	const int nk = program_.num_kept();
	BlockIndex pp_index(nk, nk);
	for (size_t b = 0; b < ne_.pp_blocks().size(); b++)
		pp_index.set(ne_.pp_blocks()[b].first, ne_.pp_blocks()[b].second, static_cast<int>(b));
	s_pattern_.block_sizes.clear();
	for (const auto& v : kept) s_pattern_.block_sizes.push_back(v.tangent);
	s_pattern_.upper_blocks.clear();
	s_row_begin_.assign(kept.size() + 1, 0);
	int off = 0;
	for (const auto& key : s_keys)
	{
		const int index = static_cast<int>(s_pattern_.upper_blocks.size());
		s_pattern_.upper_blocks.push_back(key);
		s_pp_block_.push_back(pp_index.find(key.first, key.second));
		s_offset_.push_back(off);
		off += kept[key.first].tangent * kept[key.second].tangent;
		s_row_begin_[key.first + 1] = index + 1;
	}
	// Every kept variable has its diagonal block, so every row is non-empty and the ends are set.
	S_.assign(off, 0.0);
	s_block_ptr_.resize(s_offset_.size());
	for (size_t k = 0; k < s_offset_.size(); k++) s_block_ptr_[k] = S_.data() + s_offset_[k];
}

void SchurEliminator::build_schur_terms()
{
	const int nk = program_.num_kept();
	BlockIndex s_index(nk, nk);
	for (size_t k = 0; k < s_pattern_.upper_blocks.size(); k++)
		s_index.set(s_pattern_.upper_blocks[k].first, s_pattern_.upper_blocks[k].second, static_cast<int>(k));
	const auto& pl = ne_.pl_blocks();
	pl_pos_.assign(pl.size(), 0);
	pl_term_begin_.assign(pl.size(), 0);
	for (int l = 0; l < program_.num_elim(); l++)
	{
		const auto& list = ne_.elim_pl(l);
		for (size_t x = 0; x < list.size(); x++)
		{
			pl_pos_[list[x]] = static_cast<int>(x);
			pl_term_begin_[list[x]] = static_cast<int>(term_s_offset_.size());
			for (size_t y = x; y < list.size(); y++)
				term_s_offset_.push_back(s_offset_[s_index.find(pl[list[x]].kept, pl[list[y]].kept)]);
		}
	}
}

void SchurEliminator::set_sparse(bool sparse)
{
	if (sparse != sparse_) cholesky_.reset();
	sparse_ = sparse;
}

double SchurEliminator::reduced_block_fill() const
{
	const double n = static_cast<double>(program_.num_kept());
	return n > 0 ? static_cast<double>(s_pattern_.upper_blocks.size()) / (n * (n + 1) / 2) : 1.0;
}

std::unique_ptr<SelectedInverse> SchurEliminator::selected_inverse(int columns) const
{
	return cholesky_ ? cholesky_->selected_inverse(columns) : nullptr;
}

void SchurEliminator::ensure_cholesky()
{
	if (!cholesky_ && program_.kept_dim() > 0)
		cholesky_ = sparse_ ? BlockCholesky::sparse(s_pattern_) : BlockCholesky::dense(s_pattern_);
}

template <int NL>
bool SchurEliminator::invert_damped_ll(int l, double lambda, double min_diag, double max_diag)
{
	const int nl = dim_or<NL>(program_.elim()[l].tangent);
	using Mat = Eigen::Matrix<double, NL, NL, NL == 1 ? Eigen::ColMajor : Eigen::RowMajor>;
	Eigen::Map<const Mat> H(ne_.hll(l), nl, nl);
	Eigen::Map<Mat> Hinv(Hll_inv_.data() + ne_.ll_offset(l), nl, nl);
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

template <int NP>
void SchurEliminator::start_row(int a, double lambda, double min_diag, double max_diag, double* rhs)
{
	const auto& kept = program_.kept();
	const int na = dim_or<NP>(kept[a].tangent);
	for (int k = s_row_begin_[a]; k < s_row_begin_[a + 1]; k++)
	{
		const int b = s_pattern_.upper_blocks[k].second;
		const int nb = dim_or<NP>(kept[b].tangent);
		double* S = S_.data() + s_offset_[k];
		if (s_pp_block_[k] >= 0)
			std::copy_n(ne_.hpp(s_pp_block_[k]), na * nb, S);
		else
			std::fill(S, S + na * nb, 0.0);
		if (a == b)
			for (int i = 0; i < na; i++) S[i * na + i] += damped(S[i * na + i], lambda, min_diag, max_diag);
	}
	double* r = rhs + kept[a].offset;
	const double* g = ne_.gradient();
	for (int i = 0; i < na; i++) r[i] = -g[kept[a].offset + i];
}

template <int NP, int NL>
void SchurEliminator::eliminate_into_row(int a, int pa, double* W, double* rhs)
{
	const auto& kept = program_.kept();
	const auto& pb = ne_.pl_blocks()[pa];
	const int l = pb.elim;
	const int na = dim_or<NP>(kept[a].tangent), nl = dim_or<NL>(program_.elim()[l].tangent);
	// W = H_al H_ll⁻¹ = H_laᵀ H_ll⁻¹ (na × nl).
	const double* Hla = ne_.hlp(pa);
	const double* Hinv = Hll_inv_.data() + ne_.ll_offset(l);
	for (int i = 0; i < na; i++)
		for (int k = 0; k < nl; k++)
		{
			double acc = Hla[i] * Hinv[k];
			for (int m = 1; m < nl; m++) acc += Hla[m * na + i] * Hinv[m * nl + k];
			W[i * nl + k] = acc;
		}
	// rhs_a += W g_l.
	double* r = rhs + kept[a].offset;
	const double* gl = ne_.gradient() + program_.kept_dim() + program_.elim()[l].offset;
	for (int i = 0; i < na; i++)
	{
		double acc = W[i * nl] * gl[0];
		for (int k = 1; k < nl; k++) acc += W[i * nl + k] * gl[k];
		r[i] += acc;
	}
	// S_ab −= W H_lb for the blocks (b ≥ a, l). The first is (a, l) itself: the diagonal block S_aa,
	// upper triangle only.
	const auto& list = ne_.elim_pl(l);
	const int* s_off = term_s_offset_.data() + pl_term_begin_[pa];
	if constexpr (NP > 0)
		sub_WH_upper<NP, NL>(W, Hla, na, nl, S_.data() + *s_off);
	else
		sub_WH_upper_mixed<NL>(W, Hla, na, nl, S_.data() + *s_off);
	s_off++;
	for (size_t y = static_cast<size_t>(pl_pos_[pa]) + 1; y < list.size(); y++, s_off++)
	{
		const int b = ne_.pl_blocks()[list[y]].kept;
		const int nb = dim_or<NP>(kept[b].tangent);
		if constexpr (NP > 0)
			sub_WH<NP, NP, NL>(W, ne_.hlp(list[y]), na, nb, nl, S_.data() + *s_off);
		else
			sub_WH_mixed<NL>(W, ne_.hlp(list[y]), na, nb, nl, S_.data() + *s_off);
	}
}

template <int NP, int NL>
void SchurEliminator::schur_row(int a, double lambda, double min_diag, double max_diag, double* rhs)
{
	start_row<NP>(a, lambda, min_diag, max_diag, rhs);
	const int na = dim_or<NP>(program_.kept()[a].tangent);
	constexpr bool fixed = NP > 0 && NL > 0;
	double W_fixed[fixed ? NP * NL : 1];
	std::vector<double> W_dynamic;
	for (const int pa : ne_.kept_pl(a))
	{
		double* W = W_fixed;
		if constexpr (!fixed)
		{
			const int nl = dim_or<NL>(program_.elim()[ne_.pl_blocks()[pa].elim].tangent);
			W_dynamic.resize(static_cast<size_t>(na) * nl);
			W = W_dynamic.data();
		}
		eliminate_into_row<NP, NL>(a, pa, W, rhs);
	}
	// Mirror the diagonal block's upper triangle (the back ends read full diagonal blocks).
	double* Saa = S_.data() + s_offset_[s_row_begin_[a]];
	for (int i = 0; i < na; i++)
		for (int j = 0; j < i; j++) Saa[i * na + j] = Saa[j * na + i];
}

template <int NP, int NL>
void SchurEliminator::back_substitute(int l, double* delta) const
{
	const auto& kept = program_.kept();
	const auto& v = program_.elim()[l];
	const int nl = dim_or<NL>(v.tangent);
	constexpr bool fixed = NL > 0;
	double v_fixed[fixed ? NL : 1];
	std::vector<double> v_dynamic;
	double* t = v_fixed;
	if constexpr (!fixed)
	{
		v_dynamic.resize(nl);
		t = v_dynamic.data();
	}
	const int kept_dim = program_.kept_dim();
	const double* gl = ne_.gradient() + kept_dim + v.offset;
	for (int k = 0; k < nl; k++) t[k] = -gl[k];
	for (const int pb_index : ne_.elim_pl(l))
	{
		const auto& pb = ne_.pl_blocks()[pb_index];
		const int nb = dim_or<NP>(kept[pb.kept].tangent);
		const double* H = ne_.hlp(pb_index);
		const double* dp = delta + kept[pb.kept].offset;
		for (int k = 0; k < nl; k++)
		{
			double acc = H[k * nb] * dp[0];
			for (int j = 1; j < nb; j++) acc += H[k * nb + j] * dp[j];
			t[k] -= acc;
		}
	}
	const double* Hinv = Hll_inv_.data() + ne_.ll_offset(l);
	double* dl = delta + kept_dim + v.offset;
	for (int i = 0; i < nl; i++)
	{
		double acc = Hinv[i * nl] * t[0];
		for (int k = 1; k < nl; k++) acc += Hinv[i * nl + k] * t[k];
		dl[i] = acc;
	}
}

bool SchurEliminator::solve_damped(double lambda, double min_diag, double max_diag, Eigen::VectorXd& delta)
{
	const int kept_dim = program_.kept_dim();
	delta.setZero(kept_dim + program_.elim_dim());
	const int ne = program_.num_elim(), nk = program_.num_kept();
	const int num_terms = static_cast<int>(term_s_offset_.size());
	const bool parallel = num_threads_ > 1 && (ne > kParallelMin || num_terms > kParallelMin || nk > kParallelMin);
	const int np_uniform = program_.uniform_kept_tangent(), nl_uniform = program_.uniform_elim_tangent();
	int failed = 0;
	// One parallel region: 1. damped H_ll⁻¹ per eliminated variable; 2. the reduced system
	// S = H_pp + λD − Σ_l H_pl H_ll⁻¹ H_lp and rhs = −g_p + Σ_l H_pl H_ll⁻¹ g_l, block row by block row.
	dispatch_schur_sizes(np_uniform, nl_uniform, [&](auto NPc, auto NLc) {
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
	if (kept_dim > 0)
	{
		ensure_cholesky();
		if (!cholesky_->factorize(s_block_ptr_)) return false;
		cholesky_->solve(rhs_.data());
		if (!rhs_.allFinite()) return false;
		delta.head(kept_dim) = rhs_;
	}
	// 3. Back-substitution: δ_l = H_ll⁻¹ (−g_l − Σ H_lp δ_p).
	dispatch_schur_sizes(np_uniform, nl_uniform, [&](auto NPc, auto NLc) {
		constexpr int NP = decltype(NPc)::value, NL = decltype(NLc)::value;
#pragma omp parallel for schedule(dynamic, 256) num_threads(num_threads_) if (num_threads_ > 1 && ne > kParallelMin)
		for (int l = 0; l < ne; l++) back_substitute<NP, NL>(l, delta.data());
	});
	return delta.allFinite();
}

void SchurEliminator::solve_factorized(Eigen::MatrixXd& X, const std::vector<char>& back) const
{
	const auto& kept = program_.kept();
	const auto& elim = program_.elim();
	const int kept_dim = program_.kept_dim();
	Eigen::MatrixXd T, U;
	// R_p = B_p − Σ_l H_pl H_ll⁻¹ B_l over the eliminated variables with a non-zero B_l.
	for (int l = 0; l < program_.num_elim(); l++)
	{
		const int nl = elim[l].tangent;
		const auto Bl = X.middleRows(kept_dim + elim[l].offset, nl);
		if (Bl.isZero(0)) continue;
		T = Eigen::Map<const RowMatrix>(Hll_inv_.data() + ne_.ll_offset(l), nl, nl) * Bl;
		for (const int pa : ne_.elim_pl(l))
		{
			const auto& pb = ne_.pl_blocks()[pa];
			const int na = kept[pb.kept].tangent;
			X.middleRows(kept[pb.kept].offset, na) -= Eigen::Map<const RowMatrix>(ne_.hlp(pa), nl, na).transpose() * T;
		}
	}
	if (kept_dim > 0)
	{
		Eigen::MatrixXd P = X.topRows(kept_dim);
		cholesky_->solve_columns(P.data(), static_cast<int>(P.cols()));
		X.topRows(kept_dim) = P;
	}
	for (int l = 0; l < program_.num_elim(); l++)
	{
		const int nl = elim[l].tangent;
		auto Xl = X.middleRows(kept_dim + elim[l].offset, nl);
		if (!back.empty() && !back[l])
		{
			Xl.setZero();
			continue;
		}
		U = Xl;
		for (const int pa : ne_.elim_pl(l))
		{
			const auto& pb = ne_.pl_blocks()[pa];
			const int na = kept[pb.kept].tangent;
			U -= Eigen::Map<const RowMatrix>(ne_.hlp(pa), nl, na) * X.middleRows(kept[pb.kept].offset, na);
		}
		Xl = Eigen::Map<const RowMatrix>(Hll_inv_.data() + ne_.ll_offset(l), nl, nl) * U;
	}
}
}  // namespace swba::detail
