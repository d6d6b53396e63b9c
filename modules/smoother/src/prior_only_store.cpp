#include "prior_only_store.h"

#include "conditional_mean.h"

#include <swba/linear/marginal.h>
#include <swba/linear/rank_update.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <stdexcept>

namespace swba::smoother::detail
{
namespace
{
/** F with F Fᵀ = S for a symmetric positive semi-definite S: its Cholesky factor when S is positive
 * definite, else V √D⁺ from its eigendecomposition (negative rounding clamped to zero). */
Eigen::MatrixXd psd_factor(const Eigen::MatrixXd& S)
{
	Eigen::LLT<Eigen::MatrixXd> llt(S);
	if (llt.info() == Eigen::Success) return llt.matrixL();
	Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(S);
	return es.eigenvectors() * es.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal();
}

Eigen::MatrixXd gather_rows(const Eigen::MatrixXd& M, const std::vector<int>& rows)
{
	Eigen::MatrixXd out(static_cast<Eigen::Index>(rows.size()), M.cols());
	for (std::size_t i = 0; i < rows.size(); i++) out.row(static_cast<Eigen::Index>(i)) = M.row(rows[i]);
	return out;
}

/** Columns `cols` of the first `n` rows of the symmetric matrix whose lower triangle is stored in L. */
Eigen::MatrixXd gather_symmetric_columns(const Eigen::MatrixXd& L, Eigen::Index n, const std::vector<int>& cols)
{
	Eigen::MatrixXd out(n, static_cast<Eigen::Index>(cols.size()));
	for (std::size_t j = 0; j < cols.size(); j++)
	{
		const Eigen::Index c = cols[j];
		out.col(static_cast<Eigen::Index>(j)).head(c) = L.row(c).head(c).transpose();
		out.col(static_cast<Eigen::Index>(j)).tail(n - c) = L.col(c).segment(c, n - c);
	}
	return out;
}

/** M resized to `rows` × `cols`, the new part zero. */
void grow(Eigen::MatrixXd& M, Eigen::Index rows, Eigen::Index cols)
{
	const Eigen::Index r0 = M.rows(), c0 = M.cols();
	M.conservativeResize(rows, cols);
	M.bottomRows(rows - r0).setZero();
	M.topRightCorner(r0, cols - c0).setZero();
}
}  // namespace

bool PriorOnlyStore::contains(VariableId v) const
{
	return std::any_of(members_.begin(), members_.end(), [v](const Member& m) { return m.var == v; });
}

std::vector<VariableId> PriorOnlyStore::variables() const
{
	std::vector<VariableId> out;
	for (const auto& m : members_) out.push_back(m.var);
	return out;
}

const std::vector<double>& PriorOnlyStore::linearization_point(VariableId v) const
{
	for (const auto& m : members_)
		if (m.var == v) return m.x_lin;
	throw std::out_of_range("PriorOnlyStore: variable not stored");
}

std::vector<int> PriorOnlyStore::rows_of(const std::vector<VariableId>& vars) const
{
	std::vector<int> rows;
	for (VariableId v : vars)
	{
		auto it = std::find_if(members_.begin(), members_.end(), [v](const Member& m) { return m.var == v; });
		if (it == members_.end()) throw std::invalid_argument("PriorOnlyStore: variable not stored");
		for (int r = 0; r < it->dim; r++) rows.push_back(it->offset + r);
	}
	return rows;
}

int PriorOnlyStore::allocate(int dim)
{
	for (auto it = free_.begin(); it != free_.end(); ++it)
		if (it->second == dim)
		{
			const int off = it->first;
			free_.erase(it);
			return off;
		}
	const int off = used_;
	used_ += dim;
	const Eigen::Index cap = k_.size();
	if (used_ > cap)
	{
		const Eigen::Index n = std::max<Eigen::Index>({2 * cap, used_, 48});
		k_.conservativeResize(n);
		k_.tail(n - cap).setZero();
		for (auto& [w, K] : K_) grow(K, n, K.cols());
		grow(C_, n, n);
		grow(P_, n, kMaxPending);
	}
	return off;
}

void PriorOnlyStore::free_rows(const Member& m)
{
	const Eigen::Index n = used_;
	k_.segment(m.offset, m.dim).setZero();
	for (auto& [w, K] : K_) K.middleRows(m.offset, m.dim).setZero();
	C_.middleRows(m.offset, m.dim).leftCols(n).setZero();
	C_.middleCols(m.offset, m.dim).topRows(n).setZero();
	P_.middleRows(m.offset, m.dim).setZero();
	free_.push_back({m.offset, m.dim});
}

void PriorOnlyStore::add_update(const Eigen::MatrixXd& U, double sign)
{
	const Eigen::Index n = U.rows(), r = U.cols();
	if (pending_ + r > kMaxPending) flush_updates();
	if (r > kMaxPending)
	{
		lower_rank_update(C_.topLeftCorner(n, n), U, Eigen::VectorXd::Constant(r, sign));
		return;
	}
	P_.middleCols(pending_, r).topRows(n) = U;
	P_.middleCols(pending_, r).bottomRows(P_.rows() - n).setZero();
	sign_.segment(pending_, r).setConstant(sign);
	pending_ += static_cast<int>(r);
}

void PriorOnlyStore::flush_updates()
{
	if (pending_ == 0) return;
	const Eigen::Index n = used_;
	lower_rank_update(C_.topLeftCorner(n, n), P_.topLeftCorner(n, pending_), sign_.head(pending_));
	pending_ = 0;
}

Eigen::MatrixXd PriorOnlyStore::covariance_columns(const std::vector<int>& cols) const
{
	const Eigen::Index n = used_;
	Eigen::MatrixXd out = gather_symmetric_columns(C_, n, cols);
	if (pending_ > 0)
	{
		const auto P = P_.topLeftCorner(n, pending_);
		out.noalias() += (P * sign_.head(pending_).asDiagonal()) * gather_rows(P_, cols).leftCols(pending_).transpose();
	}
	return out;
}

void PriorOnlyStore::compact_if_sparse()
{
	int free_dim = 0;
	for (const auto& f : free_) free_dim += f.second;
	if (free_dim == 0 || 2 * free_dim < used_) return;
	flush_updates();
	std::vector<int> rows;
	for (auto& m : members_)
	{
		const int off = static_cast<int>(rows.size());
		for (int r = 0; r < m.dim; r++) rows.push_back(m.offset + r);
		m.offset = off;
	}
	const Eigen::Index n = static_cast<Eigen::Index>(rows.size()), cap = std::max<Eigen::Index>(n, 48);
	Eigen::VectorXd k = Eigen::VectorXd::Zero(cap);
	Eigen::MatrixXd C = Eigen::MatrixXd::Zero(cap, cap);
	for (Eigen::Index i = 0; i < n; i++)
	{
		k[i] = k_[rows[static_cast<std::size_t>(i)]];
		for (Eigen::Index j = 0; j <= i; j++)
		{
			const auto [a, b] = std::minmax(rows[static_cast<std::size_t>(i)], rows[static_cast<std::size_t>(j)]);
			C(i, j) = C_(b, a);
		}
	}
	for (auto& [w, K] : K_)
	{
		Eigen::MatrixXd Kn = Eigen::MatrixXd::Zero(cap, K.cols());
		Kn.topRows(n) = gather_rows(K, rows);
		K = std::move(Kn);
	}
	k_ = std::move(k);
	C_ = std::move(C);
	P_ = Eigen::MatrixXd::Zero(cap, kMaxPending);
	used_ = static_cast<int>(n);
	free_.clear();
}

PriorOnlyStore::PriorSplit PriorOnlyStore::split_prior(const Problem& problem, const MarginalPrior& prior,
														const std::vector<VariableId>& vars)
{
	const auto& pvars = prior.variables();
	MarginalPrior::Partition part = prior.partition(
		problem, [&](VariableId v) { return std::find(vars.begin(), vars.end(), v) != vars.end(); });
	PriorSplit sp;
	for (std::size_t i : part.first)
	{
		const auto& var = problem.variable(pvars[i]);
		sp.joining.push_back({pvars[i], -1, var.manifold->tangent_size(), prior.linearization_points()[i], var.manifold});
	}
	for (std::size_t i : part.second)
	{
		sp.avars.push_back(pvars[i]);
		sp.adims.push_back(problem.variable(pvars[i]).manifold->tangent_size());
		sp.alin.push_back(prior.linearization_points()[i]);
	}
	if (sp.joining.size() != vars.size()) throw std::invalid_argument("PriorOnlyStore::absorb: variable not in the prior");
	sp.lcols = std::move(part.first_columns);
	sp.acols = std::move(part.second_columns);
	return sp;
}

void PriorOnlyStore::absorb(Problem& problem, MarginalPrior& prior, const std::vector<VariableId>& vars,
							double threshold)
{
	if (vars.empty()) return;
	// The prior's columns of the leaving variables (l) and of the others (a).
	PriorSplit sp = split_prior(problem, prior, vars);
	const Eigen::MatrixXd H = prior.has_information() ? prior.H() : Eigen::MatrixXd(prior.J().transpose() * prior.J());
	const Eigen::VectorXd b = prior.has_information() ? prior.b() : Eigen::VectorXd(-(prior.J().transpose() * prior.e()));
	PartitionedNormalEquations s = partition_normal_equations(H, b, sp.lcols, sp.acols);
	GaussianElimination c = swba::eliminate(std::move(s), threshold, true);
	const Eigen::MatrixXd C_ll = 0.5 * (c.conditional.covariance + c.conditional.covariance.transpose());

	// Rows for the joining variables, then the stored rows' dependence on them, K_pl (zero in new rows).
	for (auto& m : sp.joining) m.offset = allocate(m.dim);
	const Eigen::Index n = used_, nl = static_cast<Eigen::Index>(sp.lcols.size());
	Eigen::MatrixXd K_pl = Eigen::MatrixXd::Zero(n, nl);
	{
		Eigen::Index c0 = 0;
		for (const auto& m : sp.joining)
		{
			auto it = K_.find(m.var);
			if (it != K_.end())
			{
				K_pl.middleCols(c0, m.dim) = it->second.topRows(n);
				K_.erase(it);
			}
			c0 += m.dim;
		}
	}
	substitute_joining(sp, K_pl, c.conditional);
	write_joining(sp.joining, K_pl, C_ll, c.conditional.k);
	for (auto& m : sp.joining)
	{
		problem.set_constant(m.var, true);
		members_.push_back(std::move(m));
	}
	prior.assign(problem, std::move(sp.avars), std::move(c.marginal), std::move(sp.alin));
}

void PriorOnlyStore::substitute_joining(const PriorSplit& sp, const Eigen::MatrixXd& K_pl, const GaussianConditional& c)
{
	// Substitute d_l = k_l − K_la d_a + ε_l in the stored rows, then write l's own rows of K.
	const Eigen::Index n = used_;
	k_.head(n).noalias() -= K_pl * c.k;
	for (std::size_t i = 0, c0 = 0; i < sp.avars.size(); c0 += static_cast<std::size_t>(sp.adims[i]), i++)
	{
		const Eigen::MatrixXd K_la = c.K.middleCols(static_cast<Eigen::Index>(c0), sp.adims[i]);
		auto it = K_.find(sp.avars[i]);
		if (it == K_.end()) it = K_.emplace(sp.avars[i], Eigen::MatrixXd::Zero(k_.size(), sp.adims[i])).first;
		it->second.topRows(n).noalias() -= K_pl * K_la;
		Eigen::Index r0 = 0;
		for (const auto& m : sp.joining)
		{
			it->second.middleRows(m.offset, m.dim) = K_la.middleRows(r0, m.dim);
			r0 += m.dim;
		}
	}
}

void PriorOnlyStore::write_joining(const std::vector<Member>& joining, const Eigen::MatrixXd& K_pl,
								   const Eigen::MatrixXd& C_ll, const Eigen::VectorXd& k_l)
{
	const Eigen::Index n = used_;
	const Eigen::MatrixXd KC = K_pl * C_ll;
	add_update(K_pl * psd_factor(C_ll), 1.0);
	// l's rows: k_l, the cross-covariance −K_pl C_ll with every stored row (its row and its column, so
	// the lower triangle holds it whatever the slot), then C_ll among the joining variables.
	for (Eigen::Index i = 0, r0 = 0; i < static_cast<Eigen::Index>(joining.size()); r0 += joining[i].dim, i++)
	{
		const Member& m = joining[static_cast<std::size_t>(i)];
		k_.segment(m.offset, m.dim) = k_l.segment(r0, m.dim);
		C_.middleCols(m.offset, m.dim).topRows(n) = -KC.middleCols(r0, m.dim);
		C_.middleRows(m.offset, m.dim).leftCols(n) = -KC.middleCols(r0, m.dim).transpose();
	}
	for (Eigen::Index i = 0, r0 = 0; i < static_cast<Eigen::Index>(joining.size()); r0 += joining[i].dim, i++)
		for (Eigen::Index j = 0, s0 = 0; j < static_cast<Eigen::Index>(joining.size()); s0 += joining[j].dim, j++)
		{
			const Member &m = joining[static_cast<std::size_t>(i)], &q = joining[static_cast<std::size_t>(j)];
			C_.block(m.offset, q.offset, m.dim, q.dim) = C_ll.block(r0, s0, m.dim, q.dim);
		}
}

void PriorOnlyStore::release(Problem& problem, MarginalPrior& prior, const std::vector<VariableId>& vars)
{
	if (vars.empty()) return;
	const std::vector<int> lrows = rows_of(vars);
	const Eigen::Index nl = static_cast<Eigen::Index>(lrows.size());
	const Eigen::MatrixXd C_pl = covariance_columns(lrows);  // all stored rows, l's own included
	const Eigen::MatrixXd C_ll = gather_rows(C_pl, lrows);
	const Eigen::LLT<Eigen::MatrixXd> llt(C_ll);
	if (llt.info() != Eigen::Success)
		throw std::runtime_error("PriorOnlyStore::release: conditional covariance not positive definite");
	Eigen::VectorXd k_l(nl);
	for (Eigen::Index i = 0; i < nl; i++) k_l[i] = k_[lrows[static_cast<std::size_t>(i)]];

	// The prior times N(d_l; k_l − K_la d_a, C_ll): rows L⁻¹ [K_la | I], residual −L⁻¹ k_l. The
	// returning variables start at their conditional mean k_l − K_la d_a.
	std::vector<int> col_of_var;
	int n0 = 0;
	for (VariableId v : prior.variables())
	{
		col_of_var.push_back(n0);
		n0 += problem.variable(v).manifold->tangent_size();
	}
	Eigen::MatrixXd J_rows = Eigen::MatrixXd::Zero(nl, n0 + nl);
	ConditionalMean d_l(k_l);
	for (const auto& [w, K] : K_)
	{
		const int idx = active_index(prior, w);
		const Eigen::MatrixXd K_lw = gather_rows(K, lrows);
		J_rows.middleCols(col_of_var[static_cast<std::size_t>(idx)], K.cols()) = K_lw;
		d_l.condition(K_lw, active_offset(problem, prior, w, idx));
	}
	J_rows.rightCols(nl).setIdentity();
	J_rows = llt.matrixL().solve(J_rows).eval();
	const Eigen::VectorXd e_rows = -llt.matrixL().solve(k_l);
	std::vector<std::vector<double>> x_lin;
	{
		int off = 0;
		for (VariableId v : vars)
		{
			x_lin.push_back(linearization_point(v));
			const Manifold& m = *problem.variable(v).manifold;
			problem.set_value(v, d_l.value(m, x_lin.back(), off).data());
			problem.set_constant(v, false);
			off += m.tangent_size();
		}
	}

	if (vars.size() == members_.size())  // the store empties: no other variable to condition on l
	{
		clear();
		prior.append_rows(problem, vars, x_lin, J_rows, e_rows);
		return;
	}

	condition_on_released(problem, vars, lrows, C_pl, llt, k_l);
	remove_members(vars);
	prior.append_rows(problem, vars, x_lin, J_rows, e_rows);
}

void PriorOnlyStore::condition_on_released(const Problem& problem, const std::vector<VariableId>& vars,
										   const std::vector<int>& lrows, const Eigen::MatrixXd& C_pl,
										   const Eigen::LLT<Eigen::MatrixXd>& llt, const Eigen::VectorXd& k_l)
{
	const Eigen::Index n = used_;
	// The others conditioned on l as well (their mean at l's mean is unchanged): G = C_pl C_ll⁻¹,
	// k_p −= G k_l, K_p −= G K_l, K_pl = −G, C_pp −= G C_lp = W Wᵀ with W = C_pl L⁻ᵀ (l's own rows,
	// garbage, are freed below).
	const Eigen::MatrixXd Wt = llt.matrixL().solve(C_pl.transpose());
	const Eigen::MatrixXd G = llt.matrixU().solve(Wt).transpose();
	k_.head(n).noalias() -= G * k_l;
	for (auto& [w, K] : K_)
	{
		const Eigen::MatrixXd K_l = gather_rows(K, lrows);
		K.topRows(n).noalias() -= G * K_l;
	}
	{
		Eigen::Index c0 = 0;
		for (VariableId v : vars)
		{
			const int d = problem.variable(v).manifold->tangent_size();
			Eigen::MatrixXd Kv = Eigen::MatrixXd::Zero(k_.size(), d);
			Kv.topRows(n) = -G.middleCols(c0, d);
			K_[v] = std::move(Kv);
			c0 += d;
		}
	}
	add_update(Wt.transpose(), -1.0);
}

void PriorOnlyStore::remove_members(const std::vector<VariableId>& vars)
{
	for (VariableId v : vars)
	{
		auto it = std::find_if(members_.begin(), members_.end(), [v](const Member& m) { return m.var == v; });
		free_rows(*it);
		members_.erase(it);
	}
	while (!free_.empty())  // free slots at the end shrink the used rows
	{
		auto last = std::max_element(free_.begin(), free_.end());
		if (last->first + last->second != used_) break;
		used_ = last->first;
		free_.erase(last);
	}
	compact_if_sparse();
}

void PriorOnlyStore::eliminate(const std::vector<VariableId>& marg, const std::vector<int>& marg_dims,
							   const std::vector<VariableId>& keep, const std::vector<int>& keep_dims,
							   const Eigen::VectorXd& k_m, const Eigen::MatrixXd& K_m, const Eigen::MatrixXd& C_m)
{
	if (empty()) return;
	const Eigen::Index n = used_;
	Eigen::MatrixXd K_pm = Eigen::MatrixXd::Zero(n, K_m.rows());
	for (std::size_t i = 0, c0 = 0; i < marg.size(); c0 += static_cast<std::size_t>(marg_dims[i]), i++)
	{
		auto it = K_.find(marg[i]);
		if (it == K_.end()) continue;  // the store does not depend on it
		K_pm.middleCols(static_cast<Eigen::Index>(c0), marg_dims[i]) = it->second.topRows(n);
		K_.erase(it);
	}
	k_.head(n).noalias() -= K_pm * k_m;
	for (std::size_t i = 0, off = 0; i < keep.size(); off += static_cast<std::size_t>(keep_dims[i]), i++)
	{
		auto it = K_.find(keep[i]);
		if (it == K_.end()) it = K_.emplace(keep[i], Eigen::MatrixXd::Zero(k_.size(), keep_dims[i])).first;
		it->second.topRows(n).noalias() -= K_pm * K_m.middleCols(static_cast<Eigen::Index>(off), keep_dims[i]);
	}
	add_update(K_pm * psd_factor(C_m), 1.0);
}

void PriorOnlyStore::shift_active(VariableId v, const Eigen::VectorXd& t)
{
	auto it = K_.find(v);
	if (it != K_.end()) k_.noalias() -= it->second * t;
}

void PriorOnlyStore::change_active(const VariableChange& change)
{
	auto it = K_.find(change.old_var);
	if (it == K_.end()) return;
	const auto blocks = change_columns(change, it->second);
	K_.erase(it);
	for (std::size_t i = 1; i < blocks.size(); i++)
	{
		auto jt = K_.find(blocks[i].first);
		if (jt == K_.end())
			K_[blocks[i].first] = blocks[i].second;
		else
			jt->second += blocks[i].second;
	}
	K_[change.new_var] = blocks[0].second;
}

void PriorOnlyStore::set_values(Problem& problem, const MarginalPrior& prior) const
{
	if (empty()) return;
	const Eigen::Index n = used_;
	ConditionalMean d(k_.head(n));
	for (const auto& [w, K] : K_) d.condition(K.topRows(n), active_offset(problem, prior, w, active_index(prior, w)));
	for (const auto& m : members_) problem.set_value(m.var, d.value(*m.manifold, m.x_lin, m.offset).data());
}

int PriorOnlyStore::active_index(const MarginalPrior& prior, VariableId w)
{
	const int idx = prior.index_of(w);
	if (idx < 0) throw std::logic_error("PriorOnlyStore: a conditioning variable left the prior");
	return idx;
}

Eigen::VectorXd PriorOnlyStore::active_offset(const Problem& problem, const MarginalPrior& prior, VariableId w, int idx)
{
	const Manifold& m = *problem.variable(w).manifold;
	Eigen::VectorXd dw(m.tangent_size());
	m.minus(problem.value(w), prior.linearization_points()[static_cast<std::size_t>(idx)].data(), dw.data());
	return dw;
}
}  // namespace swba::smoother::detail
