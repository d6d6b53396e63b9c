#include "linear_tail.h"

#include <swba/linear/marginal.h>

#include <algorithm>
#include <stdexcept>

namespace swba::smoother::detail
{
TailConditional make_tail_conditional(const Problem& problem, const std::vector<VariableId>& keep,
									  const std::vector<std::vector<double>>& keep_lin,
									  const std::vector<VariableId>& marg, const Eigen::MatrixXd& H,
									  const Eigen::VectorXd& b, double threshold)
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
	for (VariableId v : marg)
	{
		const auto& var = problem.variable(v);
		c.vars.push_back(v);
		c.manifolds.push_back(var.manifold);
		c.x_lin.push_back(var.value);
		c.value.push_back(var.value);
	}
	const Eigen::Index nm = H.rows() - num_keep;
	if (nm < 0 || H.cols() != H.rows() || b.size() != H.rows())
		throw std::invalid_argument("make_tail_conditional: H, b and the variables' sizes disagree");
	Eigen::VectorXd s(num_keep);
	for (std::size_t i = 0, off = 0; i < keep.size(); i++)
	{
		const auto& var = problem.variable(keep[i]);
		var.manifold->minus(var.value.data(), keep_lin[i].data(), s.data() + off);
		off += static_cast<std::size_t>(c.sep_dims[i]);
	}
	c.covariance = nm > 0 ? truncated_pseudo_inverse(H.bottomRightCorner(nm, nm), threshold) : Eigen::MatrixXd();
	const Eigen::MatrixXd H_ms = H.bottomLeftCorner(nm, num_keep);
	c.K = c.covariance * H_ms;
	c.k = c.covariance * (b.tail(nm) + H_ms * s);
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
		Eigen::VectorXd d = c->k;
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
		d.noalias() -= c->K * ds;
		for (std::size_t j = 0, off = 0; j < c->vars.size(); j++)
		{
			c->manifolds[j]->plus(c->x_lin[j].data(), d.data() + off, c->value[j].data());
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

void LinearTail::change_variable(const VariableChange& change, const std::vector<double>& old_lin,
								 const std::function<std::vector<double>(VariableId)>& lin)
{
	for (auto& c : conditionals_)
	{
		const auto it = std::find(c.sep.begin(), c.sep.end(), change.old_var);
		if (it == c.sep.end()) continue;
		const std::size_t j = static_cast<std::size_t>(it - c.sep.begin());
		Eigen::Index c0 = 0;
		for (std::size_t i = 0; i < j; i++) c0 += c.sep_dims[i];
		// In the change's coordinates d'_old = d_old − (old_lin − x_lin_old), and d'_old = D (H_new d_new +
		// Σ H_i d_yi) to first order: K_old d_old splits over new_var and the y_i.
		if (!old_lin.empty())
			c.k -= c.K.middleCols(c0, 3) *
				   (Eigen::Map<const Eigen::Vector3d>(old_lin.data()) - Eigen::Map<const Eigen::Vector3d>(c.sep_lin[j].data()));
		const Eigen::MatrixXd KD = c.K.middleCols(c0, 3) * change.D;
		for (const auto& [y, Hy] : change.H_poses)
		{
			const auto yt = std::find(c.sep.begin(), c.sep.end(), y);
			if (yt != c.sep.end())
			{
				Eigen::Index cy = 0;
				for (auto i = c.sep.begin(); i != yt; ++i) cy += c.sep_dims[static_cast<std::size_t>(i - c.sep.begin())];
				c.K.middleCols(cy, Hy.cols()) += KD * Hy;
				continue;
			}
			const Eigen::Index n = c.K.cols();
			c.K.conservativeResize(Eigen::NoChange, n + Hy.cols());
			c.K.rightCols(Hy.cols()) = KD * Hy;
			c.sep.push_back(y);
			c.sep_lin.push_back(lin(y));
			c.sep_dims.push_back(static_cast<int>(Hy.cols()));
		}
		c.K.middleCols(c0, 3) = KD * change.H_new;
		c.sep[j] = change.new_var;
		c.sep_lin[j] = change.new_x_lin;
	}
}
}  // namespace swba::smoother::detail
