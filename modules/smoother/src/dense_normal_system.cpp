#include "dense_normal_system.h"

#include <swba/core/loss.h>

#include <map>
#include <stdexcept>

namespace swba::smoother::detail
{
namespace
{
/** Accumulates factor blocks into a DenseNormalSystem over a fixed variable order; the Jacobian
 * scratch buffers are reused from one factor to the next. */
class DenseNormalAssembler
{
   public:
	DenseNormalAssembler(const Problem& problem, const std::vector<VariableId>& order) : problem_(problem)
	{
		out_.offsets.push_back(0);
		for (std::size_t i = 0; i < order.size(); i++)
		{
			index_[order[i]] = static_cast<int>(i);
			out_.offsets.push_back(out_.offsets.back() + problem.variable(order[i]).manifold->tangent_size());
		}
		const int n = out_.offsets.back();
		out_.H.setZero(n, n);
		out_.b.setZero(n);
	}

	/** Offset in the system of `v`, −1 when it is not in the order (held fixed). */
	int offset_of(VariableId v) const
	{
		auto it = index_.find(v);
		return it == index_.end() ? -1 : out_.offsets[static_cast<std::size_t>(it->second)];
	}

	/** The prior's contribution from its information: H_prior and b − H (x ⊟ x_lin). */
	void add_known_prior(const MarginalPrior& prior)
	{
		// Its variables' positions in the order (the prior's variables are all kept, none fixed).
		const auto& vars = prior.variables();
		std::vector<int> poff(vars.size() + 1, 0), dst(vars.size(), -1);
		for (std::size_t i = 0; i < vars.size(); i++)
		{
			poff[i + 1] = poff[i] + problem_.variable(vars[i]).manifold->tangent_size();
			dst[i] = offset_of(vars[i]);
		}
		if (poff.back() != prior.H().rows()) throw std::logic_error("dense_normal_system: prior H has the wrong size");
		// b_prior = −Jᵀ(e + J d) = b − H d, d = x ⊟ x_lin.
		Eigen::VectorXd d(poff.back());
		for (std::size_t i = 0; i < vars.size(); i++)
			problem_.variable(vars[i]).manifold->minus(problem_.value(vars[i]), prior.linearization_points()[i].data(),
													   d.data() + poff[i]);
		const Eigen::VectorXd bp = prior.b() - prior.H() * d;
		for (std::size_t i = 0; i < vars.size(); i++)
		{
			if (dst[i] < 0) continue;
			const int ni = poff[i + 1] - poff[i];
			out_.b.segment(dst[i], ni) += bp.segment(poff[i], ni);
			for (std::size_t j = 0; j < vars.size(); j++)
				if (dst[j] >= 0)
					out_.H.block(dst[i], dst[j], ni, poff[j + 1] - poff[j]) +=
						prior.H().block(poff[i], poff[j], ni, poff[j + 1] - poff[j]);
		}
	}

	/** Factor `f` linearised at the current values (skipped and counted when it cannot be evaluated). */
	void add_factor(FactorId f)
	{
		const auto& fe = problem_.factor(f);
		const int m = fe.factor->residual_dim();
		const int k = fe.factor->num_variables();
		jac_.resize(static_cast<std::size_t>(k));
		jp_.assign(static_cast<std::size_t>(k), nullptr);
		xs_.assign(static_cast<std::size_t>(k), nullptr);
		cols_.assign(static_cast<std::size_t>(k), 0);
		slot_.assign(static_cast<std::size_t>(k), -1);
		for (int s = 0; s < k; s++)
		{
			xs_[s] = problem_.value(fe.variables[s]);
			cols_[s] = fe.factor->tangent_dims()[s];
			jac_[s].setZero(m, cols_[s]);
			jp_[s] = jac_[s].data();
			slot_[s] = offset_of(fe.variables[s]);
		}
		Eigen::VectorXd r(m);
		if (!fe.factor->evaluate_whitened(xs_.data(), r.data(), jp_.data()) || !r.allFinite())
		{
			out_.unevaluable++;
			return;
		}
		if (fe.loss) apply_loss(*fe.loss, m, r.data(), k, cols_.data(), jp_.data());
		for (int s = 0; s < k; s++)
		{
			if (slot_[s] < 0) continue;
			out_.b.segment(slot_[s], cols_[s]).noalias() -= jac_[s].transpose() * r;
			for (int t = 0; t < k; t++)
				if (slot_[t] >= 0)
					out_.H.block(slot_[s], slot_[t], cols_[s], cols_[t]).noalias() += jac_[s].transpose() * jac_[t];
		}
	}

	DenseNormalSystem take() { return std::move(out_); }

   private:
	using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
	const Problem& problem_;
	std::map<VariableId, int> index_;
	DenseNormalSystem out_;
	std::vector<RowMajor> jac_;
	std::vector<double*> jp_;
	std::vector<const double*> xs_;
	std::vector<int> cols_, slot_;
};
}  // namespace

DenseNormalSystem dense_normal_system(const Problem& problem, const std::vector<VariableId>& order,
									  const std::vector<FactorId>& factors, const MarginalPrior* known_prior)
{
	DenseNormalAssembler assembler(problem, order);
	for (FactorId f : factors)
	{
		if (known_prior && f == known_prior->factor())
			assembler.add_known_prior(*known_prior);
		else
			assembler.add_factor(f);
	}
	return assembler.take();
}
}  // namespace swba::smoother::detail
