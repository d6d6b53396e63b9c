#include "prior_only_elimination.h"

#include <swba/factors/linear_prior.h>
#include <swba/linear/marginal.h>
#include <swba/core/loss.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <map>
#include <stdexcept>

namespace swba::estimators::detail
{
bool PriorOnlyElimination::split(const Problem& problem, FactorId prior_factor, const std::vector<VariableId>& vars,
								 const std::vector<std::vector<double>>& x_lin,
								 const std::function<bool(VariableId)>& eliminable, Eigen::Index total_cols)
{
	active_.clear();
	passive_.clear();
	passive_lin_.clear();
	pcols_.clear();
	acols_.clear();
	amanifolds_.clear();
	alin_.clear();
	reduced_factor_ = -1;
	if (vars.size() != x_lin.size()) throw std::invalid_argument("PriorOnlyElimination: one x_lin per variable");
	int off = 0;
	for (std::size_t i = 0; i < vars.size(); i++)
	{
		const auto& var = problem.variable(vars[i]);
		const int n = var.manifold->tangent_size();
		const bool prior_only =
			!var.constant && var.factors.size() == 1 && *var.factors.begin() == prior_factor && eliminable(vars[i]);
		if (prior_only)
		{
			if (var.manifold->ambient_size() != n)
				throw std::invalid_argument("PriorOnlyElimination: eliminable variables must be Euclidean");
			passive_.push_back(vars[i]);
			passive_lin_.push_back(x_lin[i]);
			for (int c = 0; c < n; c++) pcols_.push_back(off + c);
		}
		else
		{
			active_.push_back({vars[i], static_cast<int>(acols_.size()), x_lin[i]});
			amanifolds_.push_back(var.manifold);
			alin_.push_back(x_lin[i]);
			for (int c = 0; c < n; c++) acols_.push_back(off + c);
		}
		off += n;
	}
	if (off != total_cols) throw std::invalid_argument("PriorOnlyElimination: the prior's size and variables disagree");
	if (passive_.empty())
	{
		active_.clear();
		return false;
	}
	return true;
}

bool PriorOnlyElimination::begin(Problem& problem, FactorId prior_factor, const std::vector<VariableId>& vars,
								 const Eigen::MatrixXd& J, const Eigen::VectorXd& e,
								 const std::vector<std::vector<double>>& x_lin, double threshold,
								 const std::function<bool(VariableId)>& eliminable)
{
	if (e.size() != J.rows()) throw std::invalid_argument("PriorOnlyElimination: J and e disagree");
	if (!split(problem, prior_factor, vars, x_lin, eliminable, J.cols())) return false;
	reduce(problem, prior_factor, partition_square_root(J, e, pcols_, acols_), threshold);
	return true;
}

bool PriorOnlyElimination::begin(Problem& problem, FactorId prior_factor, const std::vector<VariableId>& vars,
								 const Eigen::MatrixXd& H, const Eigen::VectorXd& b,
								 const std::vector<std::vector<double>>& x_lin, double threshold,
								 const std::function<bool(VariableId)>& eliminable, bool /*information_form*/)
{
	if (H.rows() != H.cols() || b.size() != H.rows()) throw std::invalid_argument("PriorOnlyElimination: H and b disagree");
	if (!split(problem, prior_factor, vars, x_lin, eliminable, H.cols())) return false;
	reduce(problem, prior_factor, partition_normal_equations(H, b, pcols_, acols_), threshold);
	return true;
}

void PriorOnlyElimination::reduce(Problem& problem, FactorId prior_factor, PartitionedNormalEquations s,
								  double threshold)
{
	ConditionalElimination c = eliminate_conditional(std::move(s), threshold);
	K_ = std::move(c.K);
	k_ = std::move(c.k);
	problem.remove_factor(prior_factor);
	for (VariableId v : passive_) problem.set_constant(v, true);
	const MarginalizationResult& red = c.marginal;
	if (red.rank > 0)
	{
		std::vector<VariableId> avars;
		for (const auto& a : active_) avars.push_back(a.var);
		reduced_factor_ = problem.add_factor(
			std::make_shared<LinearPriorFactor>(red.J, red.e, std::move(alin_), std::move(amanifolds_)), std::move(avars));
	}
}

void PriorOnlyElimination::end(Problem& problem)
{
	if (passive_.empty()) return;
	// δa = x_a ⊟ x_a,lin, then δp = k − K δa.
	Eigen::VectorXd da(K_.cols());
	for (const auto& a : active_)
		problem.variable(a.var).manifold->minus(problem.value(a.var), a.x_lin.data(), da.data() + a.offset);
	const Eigen::VectorXd dp = k_ - K_ * da;
	int off = 0;
	for (std::size_t i = 0; i < passive_.size(); i++)
	{
		const auto& lin = passive_lin_[i];
		std::vector<double> x(lin.size());
		for (std::size_t c = 0; c < lin.size(); c++) x[c] = lin[c] + dp[off + static_cast<Eigen::Index>(c)];
		off += static_cast<int>(lin.size());
		problem.set_value(passive_[i], x.data());
		problem.set_constant(passive_[i], false);
	}
	if (reduced_factor_ >= 0) problem.remove_factor(reduced_factor_);
	reduced_factor_ = -1;
	active_.clear();
	passive_.clear();
	passive_lin_.clear();
}
DenseNormalSystem dense_normal_system(const Problem& problem, const std::vector<VariableId>& order,
									  const std::vector<FactorId>& factors, const KnownPrior& prior)
{
	DenseNormalSystem out;
	std::map<VariableId, int> index;
	out.offsets.push_back(0);
	for (std::size_t i = 0; i < order.size(); i++)
	{
		index[order[i]] = static_cast<int>(i);
		out.offsets.push_back(out.offsets.back() + problem.variable(order[i]).manifold->tangent_size());
	}
	const int n = out.offsets.back();
	out.H.setZero(n, n);
	out.b.setZero(n);
	using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
	std::vector<RowMajor> jac;
	std::vector<double*> jp;
	std::vector<const double*> xs;
	std::vector<int> cols, slot;
	for (FactorId f : factors)
	{
		if (f == prior.factor && prior.H)
		{
			// Its variables' positions in `order` (the prior's variables are all kept, none fixed).
			const auto& vars = *prior.vars;
			std::vector<int> poff(vars.size() + 1, 0), dst(vars.size(), -1);
			for (std::size_t i = 0; i < vars.size(); i++)
			{
				poff[i + 1] = poff[i] + problem.variable(vars[i]).manifold->tangent_size();
				auto it = index.find(vars[i]);
				if (it != index.end()) dst[i] = out.offsets[static_cast<std::size_t>(it->second)];
			}
			if (poff.back() != prior.H->rows()) throw std::logic_error("dense_normal_system: prior H has the wrong size");
			// b_prior = −Jᵀ(e + J d) = b − H d, d = x ⊟ x_lin.
			Eigen::VectorXd d(poff.back());
			for (std::size_t i = 0; i < vars.size(); i++)
				problem.variable(vars[i]).manifold->minus(problem.value(vars[i]), (*prior.x_lin)[i].data(), d.data() + poff[i]);
			const Eigen::VectorXd bp = *prior.b - *prior.H * d;
			for (std::size_t i = 0; i < vars.size(); i++)
			{
				if (dst[i] < 0) continue;
				const int ni = poff[i + 1] - poff[i];
				out.b.segment(dst[i], ni) += bp.segment(poff[i], ni);
				for (std::size_t j = 0; j < vars.size(); j++)
					if (dst[j] >= 0)
						out.H.block(dst[i], dst[j], ni, poff[j + 1] - poff[j]) +=
							prior.H->block(poff[i], poff[j], ni, poff[j + 1] - poff[j]);
			}
			continue;
		}
		const auto& fe = problem.factor(f);
		const int m = fe.factor->residual_dim();
		const int k = fe.factor->num_variables();
		jac.resize(static_cast<std::size_t>(k));
		jp.assign(static_cast<std::size_t>(k), nullptr);
		xs.assign(static_cast<std::size_t>(k), nullptr);
		cols.assign(static_cast<std::size_t>(k), 0);
		slot.assign(static_cast<std::size_t>(k), -1);
		for (int s = 0; s < k; s++)
		{
			xs[s] = problem.value(fe.variables[s]);
			cols[s] = fe.factor->tangent_dims()[s];
			jac[s].setZero(m, cols[s]);
			jp[s] = jac[s].data();
			auto it = index.find(fe.variables[s]);
			if (it != index.end()) slot[s] = out.offsets[static_cast<std::size_t>(it->second)];
		}
		Eigen::VectorXd r(m);
		if (!fe.factor->evaluate_whitened(xs.data(), r.data(), jp.data()) || !r.allFinite()) continue;
		if (fe.loss) apply_loss(*fe.loss, m, r.data(), k, cols.data(), jp.data());
		for (int s = 0; s < k; s++)
		{
			if (slot[s] < 0) continue;
			out.b.segment(slot[s], cols[s]).noalias() -= jac[s].transpose() * r;
			for (int t = 0; t < k; t++)
				if (slot[t] >= 0) out.H.block(slot[s], slot[t], cols[s], cols[t]).noalias() += jac[s].transpose() * jac[t];
		}
	}
	return out;
}
}  // namespace swba::estimators::detail
