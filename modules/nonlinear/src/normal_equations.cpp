#include "normal_equations.h"

#include <algorithm>
#include <cmath>

#include "block_index.h"
#include "small_blocks.h"

namespace swba::detail
{
NormalEquations::NormalEquations(const Program& program, const ProgramEvaluator& evaluator, int num_threads)
	: program_(program), evaluator_(evaluator), num_threads_(std::max(1, num_threads))
{
	collect_blocks();
	sort_pp_blocks();
	lay_out_storage();
	lay_out_cache();
}

void NormalEquations::collect_blocks()
{
	const int nk = program_.num_kept(), ne = program_.num_elim();
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
	for (int a = 0; a < nk; a++) pp_block(a, a);
	BlockIndex pl_index(nk, ne);
	for (int f = 0; f < program_.num_factors(); f++)
	{
		const auto& fs = program_.factor(f);
		const int k = static_cast<int>(fs.kind.size());
		for (int s = 0; s < k; s++)
		{
			if (fs.kind[s] != kKeptSlot) continue;
			for (int t = 0; t < k; t++)
			{
				if (fs.kind[t] == kKeptSlot && fs.index[s] <= fs.index[t])
					pp_contrib_[pp_block(fs.index[s], fs.index[t])].push_back({f, s, t});
				else if (fs.kind[t] == kEliminatedSlot)
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
}

void NormalEquations::sort_pp_blocks()
{
	// Deterministic block order: pp blocks by (i, j), each with its contributions.
	std::vector<int> perm(pp_blocks_.size());
	for (size_t i = 0; i < perm.size(); i++) perm[i] = static_cast<int>(i);
	std::sort(perm.begin(), perm.end(), [&](int x, int y) { return pp_blocks_[x] < pp_blocks_[y]; });
	std::vector<std::pair<int, int>> blocks;
	std::vector<std::vector<Contribution>> contrib;
	for (size_t i = 0; i < perm.size(); i++)
	{
		blocks.push_back(pp_blocks_[perm[i]]);
		contrib.push_back(std::move(pp_contrib_[perm[i]]));
	}
	pp_blocks_ = std::move(blocks);
	pp_contrib_ = std::move(contrib);
}

void NormalEquations::lay_out_storage()
{
	const auto& kept = program_.kept();
	const auto& elim = program_.elim();
	pp_offset_.resize(pp_blocks_.size());
	int off = 0;
	for (size_t i = 0; i < pp_blocks_.size(); i++)
	{
		pp_offset_[i] = off;
		off += kept[pp_blocks_[i].first].tangent * kept[pp_blocks_[i].second].tangent;
	}
	Hpp_.assign(off, 0.0);

	// H_pl blocks, sorted by (elim, kept) so that each landmark's blocks are contiguous.
	std::sort(pl_blocks_.begin(), pl_blocks_.end(), [](const PlBlock& x, const PlBlock& y) {
		return std::make_pair(x.elim, x.kept) < std::make_pair(y.elim, y.kept);
	});
	elim_pl_.assign(elim.size(), {});
	kept_pl_.assign(kept.size(), {});
	off = 0;
	for (size_t i = 0; i < pl_blocks_.size(); i++)
	{
		auto& pb = pl_blocks_[i];
		pb.offset = off;
		off += kept[pb.kept].tangent * elim[pb.elim].tangent;
		elim_pl_[pb.elim].push_back(static_cast<int>(i));
		kept_pl_[pb.kept].push_back(static_cast<int>(i));
	}
	Hlp_.assign(off, 0.0);
	ll_offset_.resize(elim.size());
	off = 0;
	for (size_t l = 0; l < elim.size(); l++)
	{
		ll_offset_[l] = off;
		off += elim[l].tangent * elim[l].tangent;
	}
	Hll_.assign(off, 0.0);
	g_.assign(program_.kept_dim() + program_.elim_dim(), 0.0);
}

void NormalEquations::lay_out_cache()
{
	const auto& kept = program_.kept();
	const auto& elim = program_.elim();
	int off = 0;
	auto constant = [&](int f) { return !program_.factor(f).loss && program_.factor(f).factor->constant_jacobian(); };
	for (size_t b = 0; b < pp_blocks_.size(); b++)
		for (auto& c : pp_contrib_[b])
			if (constant(c.factor))
			{
				c.cache = off;
				off += kept[pp_blocks_[b].first].tangent * kept[pp_blocks_[b].second].tangent;
			}
	for (auto& pb : pl_blocks_)
		for (auto& c : pb.contrib)
			if (constant(c.factor))
			{
				c.cache = off;
				off += kept[pb.kept].tangent * elim[pb.elim].tangent;
			}
	cache_.assign(off, 0.0);
	cache_ready_.assign(off, 0);
}

void NormalEquations::add_contribution(const Contribution& c, int na, int nb, bool transpose_slots, double* H)
{
	const int sa = transpose_slots ? c.slot_b : c.slot_a, sb = transpose_slots ? c.slot_a : c.slot_b;
	const double* A = evaluator_.jacobian(c.factor, sa);
	const double* B = evaluator_.jacobian(c.factor, sb);
	const int m = program_.factor(c.factor).m;
	if (c.cache < 0)
	{
		add_AtB(A, B, m, na, nb, H);
		return;
	}
	// The cached product is the sum add_AtB adds to H (formed on zeros): H gets the same bits wherever
	// add_AtB forms the block's sum before adding it (its fixed-size kernels, block sizes 1, 2, 3, 6).
	double* P = cache_.data() + c.cache;
	if (!cache_ready_[c.cache])
	{
		std::fill(P, P + na * nb, 0.0);
		add_AtB(A, B, m, na, nb, P);
		cache_ready_[c.cache] = 1;
	}
	for (int k = 0; k < na * nb; k++) H[k] += P[k];
}

void NormalEquations::assemble_pp(int b)
{
	const auto& kept = program_.kept();
	const int na = kept[pp_blocks_[b].first].tangent, nb = kept[pp_blocks_[b].second].tangent;
	double* H = Hpp_.data() + pp_offset_[b];
	std::fill(H, H + na * nb, 0.0);
	for (const auto& c : pp_contrib_[b])
		if (evaluator_.valid(c.factor)) add_contribution(c, na, nb, false, H);
}

void NormalEquations::assemble_pl(int b)
{
	const auto& pb = pl_blocks_[b];
	const int na = program_.kept()[pb.kept].tangent, nl = program_.elim()[pb.elim].tangent;
	double* H = Hlp_.data() + pb.offset;  // H_lp = Σ J_lᵀ J_p (nl × na)
	std::fill(H, H + na * nl, 0.0);
	for (const auto& c : pb.contrib)
		if (evaluator_.valid(c.factor)) add_contribution(c, nl, na, true, H);
}

void NormalEquations::assemble_ll(int l)
{
	const auto& v = program_.elim()[l];
	const int nl = v.tangent;
	double* H = Hll_.data() + ll_offset_[l];
	double* g = g_.data() + program_.kept_dim() + v.offset;
	std::fill(H, H + nl * nl, 0.0);
	std::fill(g, g + nl, 0.0);
	for (const auto& [f, s] : program_.elim_factors(l))
	{
		if (!evaluator_.valid(f)) continue;
		const int m = program_.factor(f).m;
		add_AtB(evaluator_.jacobian(f, s), evaluator_.jacobian(f, s), m, nl, nl, H);
		add_Atr(evaluator_.jacobian(f, s), evaluator_.residual(f), m, nl, g);
	}
}

void NormalEquations::assemble_kept_gradient(int a)
{
	const auto& v = program_.kept()[a];
	double* g = g_.data() + v.offset;
	std::fill(g, g + v.tangent, 0.0);
	for (const auto& [f, s] : program_.kept_factors(a))
	{
		if (!evaluator_.valid(f)) continue;
		const auto& fs = program_.factor(f);
		add_Atr(evaluator_.jacobian(f, s), evaluator_.residual(f), fs.m, fs.factor->tangent_dims()[s], g);
	}
}

void NormalEquations::assemble()
{
	const int npp = static_cast<int>(pp_blocks_.size()), npl = static_cast<int>(pl_blocks_.size());
	const int ne = program_.num_elim(), nk = program_.num_kept();
#pragma omp parallel num_threads(num_threads_) if (program_.num_factors() > kParallelMin)
	{
#pragma omp for schedule(dynamic, 64) nowait
		for (int b = 0; b < npp; b++) assemble_pp(b);
#pragma omp for schedule(dynamic, 256) nowait
		for (int b = 0; b < npl; b++) assemble_pl(b);
#pragma omp for schedule(dynamic, 256) nowait
		for (int l = 0; l < ne; l++) assemble_ll(l);
#pragma omp for schedule(dynamic, 64)
		for (int a = 0; a < nk; a++) assemble_kept_gradient(a);
	}
}

double NormalEquations::gradient_max_norm() const
{
	double m = 0;
	for (double v : g_) m = std::max(m, std::abs(v));
	return m;
}

double NormalEquations::model_decrease(const Eigen::VectorXd& delta) const
{
	// −gᵀδ − ½ δᵀHδ with δᵀHδ summed blockwise from the undamped blocks (no H δ vector).
	const auto& kept = program_.kept();
	const auto& elim = program_.elim();
	const int kept_dim = program_.kept_dim();
	const double* d = delta.data();
	double quad = 0;
	for (size_t b = 0; b < pp_blocks_.size(); b++)
	{
		const auto [i, j] = pp_blocks_[b];
		const double q = quadratic_form(d + kept[i].offset, Hpp_.data() + pp_offset_[b], d + kept[j].offset,
										kept[i].tangent, kept[j].tangent);
		quad += i == j ? q : 2 * q;
	}
	for (const auto& pb : pl_blocks_)
		quad += 2 * quadratic_form(d + kept_dim + elim[pb.elim].offset, Hlp_.data() + pb.offset,
								   d + kept[pb.kept].offset, elim[pb.elim].tangent, kept[pb.kept].tangent);
	for (size_t l = 0; l < elim.size(); l++)
	{
		const double* dl = d + kept_dim + elim[l].offset;
		quad += quadratic_form(dl, Hll_.data() + ll_offset_[l], dl, elim[l].tangent, elim[l].tangent);
	}
	Eigen::Map<const Eigen::VectorXd> g(g_.data(), g_.size());
	return -g.dot(delta) - 0.5 * quad;
}
double NormalEquations::factor_model_decrease(int f, const Eigen::VectorXd& delta) const
{
	if (!evaluator_.valid(f)) return 0.0;
	const auto& fs = program_.factor(f);
	Eigen::VectorXd jd = Eigen::VectorXd::Zero(fs.m);
	for (size_t s = 0; s < fs.kind.size(); s++)
	{
		if (fs.kind[s] == kConstantSlot) continue;
		const bool kept = fs.kind[s] == kKeptSlot;
		const auto& v = kept ? program_.kept()[fs.index[s]] : program_.elim()[fs.index[s]];
		const int offset = kept ? v.offset : program_.kept_dim() + v.offset;
		using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
		jd += Eigen::Map<const RowMajor>(evaluator_.jacobian(f, static_cast<int>(s)), fs.m, v.tangent) *
			  delta.segment(offset, v.tangent);
	}
	const Eigen::Map<const Eigen::VectorXd> r(evaluator_.residual(f), fs.m);
	return -r.dot(jd) - 0.5 * jd.squaredNorm();
}
}  // namespace swba::detail
