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

NormalEquations::NormalEquations(Problem& problem, bool use_schur, bool sparse, int num_threads)
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
		if (use_schur_ && v.group == Group::Eliminable)
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
	// H_pp blocks.
	std::map<std::pair<int, int>, int> pp_index;
	auto pp_block = [&](int a, int b) {
		auto key = std::make_pair(std::min(a, b), std::max(a, b));
		auto it = pp_index.find(key);
		if (it != pp_index.end()) return it->second;
		const int idx = static_cast<int>(pp_blocks_.size());
		pp_index.emplace(key, idx);
		pp_blocks_.push_back(key);
		pp_contrib_.emplace_back();
		return idx;
	};
	pp_diag_block_.resize(kept_.size());
	for (int a = 0; a < num_kept(); a++) pp_diag_block_[a] = pp_block(a, a);
	std::map<std::pair<int, int>, int> pl_index;
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
					auto key = std::make_pair(fs.index[s], fs.index[t]);
					auto it = pl_index.find(key);
					int idx;
					if (it == pl_index.end())
					{
						idx = static_cast<int>(pl_blocks_.size());
						pl_index.emplace(key, idx);
						pl_blocks_.push_back({fs.index[s], fs.index[t], 0, {}});
					}
					else
						idx = it->second;
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
		pp_index.clear();
		for (size_t i = 0; i < pp_blocks_.size(); i++) pp_index[pp_blocks_[i]] = static_cast<int>(i);
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
	Hpl_.assign(off, 0.0);
	W_.assign(off, 0.0);
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

	// Reduced system pattern: H_pp blocks ∪ pairs of kept variables sharing an eliminated one.
	std::map<std::pair<int, int>, std::vector<SchurTerm>> terms;
	for (const auto& b : pp_blocks_) terms[b];
	for (size_t l = 0; l < elim_.size(); l++)
	{
		const auto& list = elim_pl_[l];
		for (size_t x = 0; x < list.size(); x++)
			for (size_t y = x; y < list.size(); y++)
			{
				// list is sorted by kept index, so pl_blocks_[list[x]].kept ≤ pl_blocks_[list[y]].kept.
				terms[{pl_blocks_[list[x]].kept, pl_blocks_[list[y]].kept}].push_back({list[x], list[y]});
			}
	}
	s_pattern_.block_sizes.clear();
	for (const auto& v : kept_) s_pattern_.block_sizes.push_back(v.tangent);
	s_pattern_.upper_blocks.clear();
	s_terms_.clear();
	s_pp_block_.clear();
	s_offset_.clear();
	off = 0;
	for (auto& [key, list] : terms)
	{
		s_pattern_.upper_blocks.push_back(key);
		s_terms_.push_back(std::move(list));
		auto it = pp_index.find(key);
		s_pp_block_.push_back(it == pp_index.end() ? -1 : it->second);
		s_offset_.push_back(off);
		off += kept_[key.first].tangent * kept_[key.second].tangent;
	}
	S_.assign(off, 0.0);
	if (kept_dim_ > 0)
		cholesky_ = sparse_ ? BlockCholesky::sparse(s_pattern_) : BlockCholesky::dense(s_pattern_);
}

double NormalEquations::evaluate(bool want_jacobians, int* dropped, int* newly_dropped)
{
	const int nf = num_factors();
	std::vector<char> was_valid;
	if (newly_dropped) was_valid = valid_;
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
		for (int f = 0; f < nf; f++) *newly_dropped += (was_valid[f] && !valid_[f]) ? 1 : 0;
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
			double* H = Hpl_.data() + pb.offset;
			std::fill(H, H + na * nl, 0.0);
			for (const auto& c : pb.contrib)
			{
				if (!valid_[c.factor]) continue;
				add_AtB(jac(c.factor, c.slot_a), jac(c.factor, c.slot_b), factors_[c.factor].m, na, nl, H);
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

bool NormalEquations::solve_damped(double lambda, double min_diag, double max_diag, Eigen::VectorXd& delta)
{
	delta.setZero(kept_dim_ + elim_dim_);
	auto damp = [&](double d) { return lambda * std::clamp(d, min_diag, max_diag); };
	bool ok = true;
	// 1. Damped H_ll⁻¹ and W = H_pl H_ll⁻¹ per eliminated variable.
	const int ne = num_elim();
#pragma omp parallel for schedule(dynamic, 256) num_threads(num_threads_) reduction(&& : ok) if (ne > kParallelMin)
	for (int l = 0; l < ne; l++)
	{
		const int nl = elim_[l].tangent;
		Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> H(
			Hll_.data() + ll_offset_[l], nl, nl);
		Eigen::MatrixXd Hd = H;
		for (int i = 0; i < nl; i++) Hd(i, i) += damp(H(i, i));
		Eigen::LLT<Eigen::MatrixXd> llt(Hd);
		if (llt.info() != Eigen::Success)
		{
			ok = false;
			continue;
		}
		Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> Hinv(
			Hll_inv_.data() + ll_offset_[l], nl, nl);
		Hinv = llt.solve(Eigen::MatrixXd::Identity(nl, nl));
		for (int b : elim_pl_[l])
		{
			const auto& pb = pl_blocks_[b];
			set_AS(Hpl_.data() + pb.offset, Hinv.data(), kept_[pb.kept].tangent, nl, W_.data() + pb.offset);
		}
	}
	if (!ok) return false;
	// 2. Reduced system S = H_pp + λD − Σ W H_plᵀ, rhs = −g_p + Σ W g_l.
	const int ns = static_cast<int>(s_terms_.size());
	std::vector<const double*> blocks(ns);
#pragma omp parallel for schedule(dynamic, 32) num_threads(num_threads_) if (ns > kParallelMin / 8)
	for (int k = 0; k < ns; k++)
	{
		const auto [a, b] = s_pattern_.upper_blocks[k];
		const int na = kept_[a].tangent, nb = kept_[b].tangent;
		double* S = S_.data() + s_offset_[k];
		if (s_pp_block_[k] >= 0)
			std::copy_n(Hpp_.data() + pp_offset_[s_pp_block_[k]], na * nb, S);
		else
			std::fill(S, S + na * nb, 0.0);
		if (a == b)
			for (int i = 0; i < na; i++) S[i * na + i] += damp(S[i * na + i]);
		for (const auto& t : s_terms_[k])
		{
			const int nl = elim_[pl_blocks_[t.pl_a].elim].tangent;
			sub_ABt(W_.data() + pl_blocks_[t.pl_a].offset, Hpl_.data() + pl_blocks_[t.pl_b].offset, na, nb, nl, S);
		}
		blocks[k] = S;
	}
	Eigen::VectorXd rhs(kept_dim_);
	const int nk = num_kept();
#pragma omp parallel for schedule(dynamic, 64) num_threads(num_threads_) if (nk > kParallelMin / 8)
	for (int a = 0; a < nk; a++)
	{
		const int na = kept_[a].tangent;
		double* r = rhs.data() + kept_[a].offset;
		for (int i = 0; i < na; i++) r[i] = -g_[kept_[a].offset + i];
		for (int b : kept_pl_[a])
		{
			const auto& pb = pl_blocks_[b];
			add_Ax(W_.data() + pb.offset, g_.data() + kept_dim_ + elim_[pb.elim].offset, na,
				   elim_[pb.elim].tangent, +1.0, r);
		}
	}
	if (kept_dim_ > 0)
	{
		if (!cholesky_->factorize(blocks)) return false;
		cholesky_->solve(rhs.data());
		if (!rhs.allFinite()) return false;
		delta.head(kept_dim_) = rhs;
	}
	// 3. Back-substitution: δ_l = H_ll⁻¹ (−g_l − Σ H_plᵀ δ_p).
#pragma omp parallel for schedule(dynamic, 256) num_threads(num_threads_) if (ne > kParallelMin)
	for (int l = 0; l < ne; l++)
	{
		const int nl = elim_[l].tangent;
		Eigen::VectorXd v(nl);
		for (int i = 0; i < nl; i++) v[i] = -g_[kept_dim_ + elim_[l].offset + i];
		for (int b : elim_pl_[l])
		{
			const auto& pb = pl_blocks_[b];
			add_Atx(Hpl_.data() + pb.offset, delta.data() + kept_[pb.kept].offset, kept_[pb.kept].tangent, nl,
					-1.0, v.data());
		}
		Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> Hinv(
			Hll_inv_.data() + ll_offset_[l], nl, nl);
		delta.segment(kept_dim_ + elim_[l].offset, nl) = Hinv * v;
	}
	return delta.allFinite();
}

double NormalEquations::model_decrease(const Eigen::VectorXd& delta) const
{
	// −gᵀδ − ½ δᵀ H δ, with H δ computed blockwise from the undamped blocks.
	Eigen::Map<const Eigen::VectorXd> g(g_.data(), g_.size());
	Eigen::VectorXd Hd = Eigen::VectorXd::Zero(delta.size());
	for (size_t b = 0; b < pp_blocks_.size(); b++)
	{
		const auto [i, j] = pp_blocks_[b];
		const int ni = kept_[i].tangent, nj = kept_[j].tangent;
		Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> H(
			Hpp_.data() + pp_offset_[b], ni, nj);
		Hd.segment(kept_[i].offset, ni) += H * delta.segment(kept_[j].offset, nj);
		if (i != j) Hd.segment(kept_[j].offset, nj) += H.transpose() * delta.segment(kept_[i].offset, ni);
	}
	for (const auto& pb : pl_blocks_)
	{
		const int na = kept_[pb.kept].tangent, nl = elim_[pb.elim].tangent;
		Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> H(
			Hpl_.data() + pb.offset, na, nl);
		const int lo = kept_dim_ + elim_[pb.elim].offset;
		Hd.segment(kept_[pb.kept].offset, na) += H * delta.segment(lo, nl);
		Hd.segment(lo, nl) += H.transpose() * delta.segment(kept_[pb.kept].offset, na);
	}
	for (size_t l = 0; l < elim_.size(); l++)
	{
		const int nl = elim_[l].tangent;
		Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> H(
			Hll_.data() + ll_offset_[l], nl, nl);
		const int lo = kept_dim_ + elim_[l].offset;
		Hd.segment(lo, nl) += H * delta.segment(lo, nl);
	}
	return -g.dot(delta) - 0.5 * delta.dot(Hd);
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
