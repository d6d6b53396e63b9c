#include "prior_only_store.h"

#include <swba/linear/marginal.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <stdexcept>

namespace swba::smoother::detail
{
namespace
{
/** The inverse of a symmetric positive semi-definite block: by Cholesky when it is clearly positive
 * definite, else the thresholded pseudo-inverse (as swba::eliminate_conditional applies it). */
Eigen::MatrixXd spd_inverse(const Eigen::MatrixXd& A, double threshold)
{
	Eigen::LLT<Eigen::MatrixXd> llt(A);
	if (llt.info() == Eigen::Success)
	{
		const Eigen::VectorXd d = llt.matrixL().toDenseMatrix().diagonal().cwiseAbs2();
		if (d.minCoeff() > threshold * d.maxCoeff())
			return llt.solve(Eigen::MatrixXd::Identity(A.rows(), A.cols()));
	}
	return truncated_pseudo_inverse(A, threshold);
}

Eigen::MatrixXd gather_rows(const Eigen::MatrixXd& M, const std::vector<int>& rows)
{
	Eigen::MatrixXd out(static_cast<Eigen::Index>(rows.size()), M.cols());
	for (std::size_t i = 0; i < rows.size(); i++) out.row(static_cast<Eigen::Index>(i)) = M.row(rows[i]);
	return out;
}

Eigen::MatrixXd gather(const Eigen::MatrixXd& M, const std::vector<int>& rows, const std::vector<int>& cols)
{
	Eigen::MatrixXd out(static_cast<Eigen::Index>(rows.size()), static_cast<Eigen::Index>(cols.size()));
	for (std::size_t j = 0; j < cols.size(); j++)
		for (std::size_t i = 0; i < rows.size(); i++)
			out(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = M(rows[i], cols[j]);
	return out;
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

void PriorOnlyStore::remove_rows(const std::vector<int>& drop)
{
	std::vector<char> dropped(static_cast<std::size_t>(dim()), 0);
	for (int r : drop) dropped[static_cast<std::size_t>(r)] = 1;
	std::vector<int> keep;
	for (int r = 0; r < dim(); r++)
		if (!dropped[static_cast<std::size_t>(r)]) keep.push_back(r);
	Eigen::VectorXd k(static_cast<Eigen::Index>(keep.size()));
	for (std::size_t i = 0; i < keep.size(); i++) k[static_cast<Eigen::Index>(i)] = k_[keep[i]];
	k_ = std::move(k);
	for (auto& [v, K] : K_) K = gather_rows(K, keep);
	C_ = gather(C_, keep, keep);
	std::vector<Member> members;
	int off = 0;
	for (auto& m : members_)
		if (!dropped[static_cast<std::size_t>(m.offset)])
		{
			m.offset = off;
			off += m.dim;
			members.push_back(std::move(m));
		}
	members_ = std::move(members);
}

void PriorOnlyStore::absorb(Problem& problem, MarginalPrior& prior, const std::vector<VariableId>& vars,
							double threshold)
{
	if (vars.empty()) return;
	// The prior's columns of the leaving variables (l) and of the others (a).
	std::vector<int> lcols, acols;
	std::vector<VariableId> avars;
	std::vector<int> adims;
	std::vector<std::vector<double>> alin;
	std::vector<Member> joining;
	const auto& pvars = prior.variables();
	int off = 0;
	for (std::size_t i = 0; i < pvars.size(); i++)
	{
		const auto& var = problem.variable(pvars[i]);
		const int n = var.manifold->tangent_size();
		const bool leaving = std::find(vars.begin(), vars.end(), pvars[i]) != vars.end();
		for (int c = 0; c < n; c++) (leaving ? lcols : acols).push_back(off + c);
		if (leaving)
			joining.push_back({pvars[i], 0, n, prior.linearization_points()[i], var.manifold});
		else
		{
			avars.push_back(pvars[i]);
			adims.push_back(n);
			alin.push_back(prior.linearization_points()[i]);
		}
		off += n;
	}
	if (joining.size() != vars.size()) throw std::invalid_argument("PriorOnlyStore::absorb: variable not in the prior");
	Eigen::MatrixXd H = prior.has_information() ? prior.H() : Eigen::MatrixXd(prior.J().transpose() * prior.J());
	Eigen::VectorXd b = prior.has_information() ? prior.b() : Eigen::VectorXd(-(prior.J().transpose() * prior.e()));
	PartitionedNormalEquations s = partition_normal_equations(H, b, lcols, acols);
	const Eigen::MatrixXd C_ll = spd_inverse(s.Hpp, threshold);
	ConditionalElimination c = eliminate_conditional(std::move(s), threshold);

	// The stored rows depend on l through K_pl: substitute d_l = k_l − K_la d_a + ε_l.
	const int np = dim(), nl = static_cast<int>(lcols.size());
	Eigen::MatrixXd K_pl = Eigen::MatrixXd::Zero(np, nl);
	{
		int c0 = 0;
		for (const auto& m : joining)
		{
			auto it = K_.find(m.var);
			if (it != K_.end()) K_pl.middleCols(c0, m.dim) = it->second;
			if (it != K_.end()) K_.erase(it);
			c0 += m.dim;
		}
	}
	const int N = np + nl;
	Eigen::VectorXd k(N);
	k.head(np) = k_ - K_pl * c.k;
	k.tail(nl) = c.k;
	k_ = std::move(k);
	for (std::size_t i = 0, c0 = 0; i < avars.size(); c0 += static_cast<std::size_t>(adims[i]), i++)
	{
		const Eigen::MatrixXd K_la = c.K.middleCols(static_cast<Eigen::Index>(c0), adims[i]);
		Eigen::MatrixXd Kw = Eigen::MatrixXd::Zero(N, adims[i]);
		auto it = K_.find(avars[i]);
		if (it != K_.end()) Kw.topRows(np) = it->second;
		Kw.topRows(np).noalias() -= K_pl * K_la;
		Kw.bottomRows(nl) = K_la;
		K_[avars[i]] = std::move(Kw);
	}
	Eigen::MatrixXd C(N, N);
	const Eigen::MatrixXd KC = K_pl * C_ll;
	C.topLeftCorner(np, np) = C_;
	C.topLeftCorner(np, np).noalias() += KC * K_pl.transpose();
	C.topRightCorner(np, nl) = -KC;
	C.bottomLeftCorner(nl, np) = -KC.transpose();
	C.bottomRightCorner(nl, nl) = C_ll;
	C_ = std::move(C);
	int row = np;
	for (auto& m : joining)
	{
		m.offset = row;
		row += m.dim;
		problem.set_constant(m.var, true);
		members_.push_back(std::move(m));
	}
	prior.assign(problem, std::move(avars), std::move(c.marginal), std::move(alin));
}

void PriorOnlyStore::release(Problem& problem, MarginalPrior& prior, const std::vector<VariableId>& vars)
{
	if (vars.empty()) return;
	const std::vector<int> lrows = rows_of(vars);
	std::vector<int> prows;
	{
		std::vector<char> in_l(static_cast<std::size_t>(dim()), 0);
		for (int r : lrows) in_l[static_cast<std::size_t>(r)] = 1;
		for (int r = 0; r < dim(); r++)
			if (!in_l[static_cast<std::size_t>(r)]) prows.push_back(r);
	}
	const Eigen::MatrixXd C_ll = gather(C_, lrows, lrows);
	const Eigen::MatrixXd C_pl = gather(C_, prows, lrows);
	const Eigen::LLT<Eigen::MatrixXd> llt(C_ll);
	if (llt.info() != Eigen::Success)
		throw std::runtime_error("PriorOnlyStore::release: conditional covariance not positive definite");
	const Eigen::Index nl = static_cast<Eigen::Index>(lrows.size());
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
	Eigen::VectorXd d_l = k_l;
	for (const auto& [w, K] : K_)
	{
		const int idx = prior.index_of(w);
		if (idx < 0) throw std::logic_error("PriorOnlyStore::release: a conditioning variable left the prior");
		const Eigen::MatrixXd K_lw = gather_rows(K, lrows);
		J_rows.middleCols(col_of_var[static_cast<std::size_t>(idx)], K.cols()) = K_lw;
		Eigen::VectorXd dw(K.cols());
		problem.variable(w).manifold->minus(problem.value(w), prior.linearization_points()[static_cast<std::size_t>(idx)].data(),
											dw.data());
		d_l.noalias() -= K_lw * dw;
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
			std::vector<double> x(x_lin.back().size());
			m.plus(x_lin.back().data(), d_l.data() + off, x.data());
			problem.set_value(v, x.data());
			problem.set_constant(v, false);
			off += m.tangent_size();
		}
	}

	// The others conditioned on l as well (their mean at l's mean is unchanged): G = C_pl C_ll⁻¹,
	// k_p −= G k_l, K_p −= G K_l, K_pl = −G, C_pp −= G C_lp.
	const Eigen::MatrixXd G = llt.solve(C_pl.transpose()).transpose();
	for (std::size_t i = 0; i < prows.size(); i++) k_[prows[i]] -= G.row(static_cast<Eigen::Index>(i)).dot(k_l);
	for (auto& [w, K] : K_)
	{
		const Eigen::MatrixXd K_l = gather_rows(K, lrows);
		for (std::size_t i = 0; i < prows.size(); i++)
			K.row(prows[i]).noalias() -= G.row(static_cast<Eigen::Index>(i)) * K_l;
	}
	{
		int c0 = 0;
		for (VariableId v : vars)
		{
			const int n = problem.variable(v).manifold->tangent_size();
			Eigen::MatrixXd Kv = Eigen::MatrixXd::Zero(dim(), n);
			for (std::size_t i = 0; i < prows.size(); i++)
				Kv.row(prows[i]) = -G.row(static_cast<Eigen::Index>(i)).segment(c0, n);
			K_[v] = std::move(Kv);
			c0 += n;
		}
	}
	Eigen::MatrixXd C_pp = gather(C_, prows, prows);
	C_pp.noalias() -= G * C_pl.transpose();
	remove_rows(lrows);
	C_ = std::move(C_pp);
	prior.append_rows(problem, vars, x_lin, J_rows, e_rows);
}

void PriorOnlyStore::eliminate(const std::vector<VariableId>& marg, const std::vector<int>& marg_dims,
							   const std::vector<VariableId>& keep, const std::vector<int>& keep_dims,
							   const Eigen::VectorXd& k_m, const Eigen::MatrixXd& K_m, const Eigen::MatrixXd& C_m)
{
	if (empty()) return;
	Eigen::MatrixXd K_pm = Eigen::MatrixXd::Zero(dim(), K_m.rows());
	for (std::size_t i = 0, c0 = 0; i < marg.size(); c0 += static_cast<std::size_t>(marg_dims[i]), i++)
	{
		auto it = K_.find(marg[i]);
		if (it == K_.end()) continue;  // the store does not depend on it
		K_pm.middleCols(static_cast<Eigen::Index>(c0), marg_dims[i]) = it->second;
		K_.erase(it);
	}
	k_.noalias() -= K_pm * k_m;
	for (std::size_t i = 0, off = 0; i < keep.size(); off += static_cast<std::size_t>(keep_dims[i]), i++)
	{
		const Eigen::MatrixXd upd = K_pm * K_m.middleCols(static_cast<Eigen::Index>(off), keep_dims[i]);
		auto it = K_.find(keep[i]);
		if (it == K_.end())
			K_[keep[i]] = -upd;
		else
			it->second -= upd;
	}
	const Eigen::MatrixXd KC = K_pm * C_m;
	C_.noalias() += KC * K_pm.transpose();
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
	const Eigen::MatrixXd KD = it->second * change.D;
	K_.erase(it);
	for (const auto& [y, Hy] : change.H_poses)
	{
		const Eigen::MatrixXd upd = KD * Hy;
		auto jt = K_.find(y);
		if (jt == K_.end())
			K_[y] = upd;
		else
			jt->second += upd;
	}
	K_[change.new_var] = KD * change.H_new;
}

void PriorOnlyStore::set_values(Problem& problem, const MarginalPrior& prior) const
{
	if (empty()) return;
	Eigen::VectorXd d = k_;
	for (const auto& [w, K] : K_)
	{
		const int idx = prior.index_of(w);
		if (idx < 0) throw std::logic_error("PriorOnlyStore::set_values: a conditioning variable left the prior");
		Eigen::VectorXd dw(K.cols());
		problem.variable(w).manifold->minus(problem.value(w), prior.linearization_points()[static_cast<std::size_t>(idx)].data(),
											dw.data());
		d.noalias() -= K * dw;
	}
	for (const auto& m : members_)
	{
		std::vector<double> x(m.x_lin.size());
		m.manifold->plus(m.x_lin.data(), d.data() + m.offset, x.data());
		problem.set_value(m.var, x.data());
	}
}
}  // namespace swba::smoother::detail
