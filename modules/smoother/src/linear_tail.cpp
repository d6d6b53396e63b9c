#include "linear_tail.h"

#include "conditional_mean.h"

#include <swba/linear/marginal.h>

#include <algorithm>
#include <stdexcept>

namespace swba::smoother::detail
{
TailConditional make_tail_conditional(const Problem& problem, const std::vector<VariableId>& keep,
									  const std::vector<std::vector<double>>& keep_lin,
									  const std::vector<VariableId>& marg, GaussianConditional g)
{
	TailConditional c;
	Eigen::Index num_keep = 0;
	for (std::size_t i = 0; i < keep.size(); i++)
	{
		const auto& var = problem.variable(keep[i]);
		c.sep.push_back(keep[i]);
		c.sep_lin.push_back(keep_lin[i]);
		c.sep_dims.push_back(var.manifold->tangent_size());
		num_keep += var.manifold->tangent_size();
	}
	Eigen::Index num_marg = 0;
	for (VariableId v : marg)
	{
		const auto& var = problem.variable(v);
		c.vars.push_back(v);
		c.dims.push_back(var.manifold->tangent_size());
		c.manifolds.push_back(var.manifold);
		c.x_lin.push_back(var.value);
		c.value.push_back(var.value);
		num_marg += var.manifold->tangent_size();
	}
	if (num_marg == 0)  // nothing but constants left: an empty conditional over the separator
	{
		g.K.setZero(0, num_keep);
		g.k.setZero(0);
	}
	if (g.K.rows() != num_marg || g.K.cols() != num_keep || g.covariance.rows() != num_marg)
		throw std::invalid_argument("make_tail_conditional: the conditional and the variables' sizes disagree");
	Eigen::VectorXd s(num_keep);
	for (std::size_t i = 0, off = 0; i < keep.size(); i++)
	{
		const auto& var = problem.variable(keep[i]);
		var.manifold->minus(var.value.data(), keep_lin[i].data(), s.data() + off);
		off += static_cast<std::size_t>(c.sep_dims[i]);
	}
	c.covariance = std::move(g.covariance);
	c.K = std::move(g.K);
	c.k = std::move(g.k);
	c.k.noalias() += c.K * s;
	return c;
}

void LinearTail::push(TailConditional c) { conditionals_.push_back(std::move(c)); }

void LinearTail::pop_front() { conditionals_.pop_front(); }

const std::vector<double>* LinearTail::value(VariableId v) const
{
	for (const auto& c : conditionals_)
	{
		const auto it = std::find(c.vars.begin(), c.vars.end(), v);
		if (it != c.vars.end()) return &c.value[static_cast<std::size_t>(it - c.vars.begin())];
		const auto jt = c.constants.find(v);
		if (jt != c.constants.end()) return &jt->second;
	}
	return nullptr;
}

void LinearTail::back_substitute(const Problem& problem)
{
	for (auto c = conditionals_.rbegin(); c != conditionals_.rend(); ++c)
	{
		if (c->vars.empty()) continue;
		ConditionalMean mean(c->k);
		Eigen::VectorXd ds(c->K.cols());
		for (std::size_t i = 0, off = 0; i < c->sep.size(); i++)
		{
			const VariableId v = c->sep[i];
			if (problem.has_variable(v))
				problem.variable(v).manifold->minus(problem.value(v), c->sep_lin[i].data(), ds.data() + off);
			else
				manifold_of(v)->minus(value(v)->data(), c->sep_lin[i].data(), ds.data() + off);
			off += static_cast<std::size_t>(c->sep_dims[i]);
		}
		mean.condition(c->K, ds);
		for (std::size_t j = 0, off = 0; j < c->vars.size(); j++)
		{
			c->value[j] = mean.value(*c->manifolds[j], c->x_lin[j], static_cast<Eigen::Index>(off));
			off += static_cast<std::size_t>(c->manifolds[j]->tangent_size());
		}
	}
}

const Manifold* LinearTail::manifold_of(VariableId v) const
{
	for (const auto& c : conditionals_)
	{
		const auto it = std::find(c.vars.begin(), c.vars.end(), v);
		if (it != c.vars.end()) return c.manifolds[static_cast<std::size_t>(it - c.vars.begin())].get();
	}
	throw std::logic_error("LinearTail: a separator variable left the problem without a conditional");
}

void LinearTail::change_variable(const VariableChange& change, const Manifold& old_manifold,
								 const std::vector<double>& old_lin,
								 const std::function<std::vector<double>(VariableId)>& lin)
{
	for (auto& c : conditionals_)
	{
		const auto it = std::find(c.sep.begin(), c.sep.end(), change.old_var);
		if (it == c.sep.end()) continue;
		const std::size_t j = static_cast<std::size_t>(it - c.sep.begin());
		const Eigen::Index c0 = column_of(c, j), n_old = c.sep_dims[j];
		// In the change's coordinates d'_old = d_old − (old_lin ⊟ x_lin_old) (exact for a Euclidean
		// old_var), and the change splits K_old d'_old over new_var and the y_i.
		if (!old_lin.empty())
		{
			Eigen::VectorXd t(n_old);
			old_manifold.minus(old_lin.data(), c.sep_lin[j].data(), t.data());
			c.k -= c.K.middleCols(c0, n_old) * t;
		}
		const auto blocks = change_columns(change, c.K.middleCols(c0, n_old));
		for (std::size_t i = 1; i < blocks.size(); i++)
		{
			const auto& [y, Ky] = blocks[i];
			const auto yt = std::find(c.sep.begin(), c.sep.end(), y);
			if (yt != c.sep.end())
			{
				c.K.middleCols(column_of(c, static_cast<std::size_t>(yt - c.sep.begin())), Ky.cols()) += Ky;
				continue;
			}
			const Eigen::Index n = c.K.cols();
			c.K.conservativeResize(Eigen::NoChange, n + Ky.cols());
			c.K.rightCols(Ky.cols()) = Ky;
			c.sep.push_back(y);
			c.sep_lin.push_back(lin(y));
			c.sep_dims.push_back(static_cast<int>(Ky.cols()));
		}
		const Eigen::MatrixXd& K_new = blocks[0].second;
		if (K_new.cols() == n_old)
			c.K.middleCols(c0, n_old) = K_new;
		else
		{
			Eigen::MatrixXd K(c.K.rows(), c.K.cols() - n_old + K_new.cols());
			K << c.K.leftCols(c0), K_new, c.K.rightCols(c.K.cols() - c0 - n_old);
			c.K = std::move(K);
		}
		c.sep[j] = change.new_var;
		c.sep_lin[j] = change.new_x_lin;
		c.sep_dims[j] = static_cast<int>(K_new.cols());
	}
}

Eigen::Index LinearTail::column_of(const TailConditional& c, std::size_t j)
{
	Eigen::Index c0 = 0;
	for (std::size_t i = 0; i < j; i++) c0 += c.sep_dims[i];
	return c0;
}
}  // namespace swba::smoother::detail
