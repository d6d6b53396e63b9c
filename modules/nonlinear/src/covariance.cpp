// Marginal covariances from the solver's factorisation: the undamped Schur system factorised once,
// then one solve per tangent coordinate of a requested variable (covariance.h).
#include <swba/nonlinear/covariance.h>

#include "covariance_recovery.h"
#include "solver_context.h"

#include <Eigen/Cholesky>
#include <chrono>
#include <stdexcept>

namespace swba
{
namespace detail
{
namespace
{
using Clock = std::chrono::steady_clock;

/** Where a variable sits in the solver's [kept; eliminated] vector. */
struct Slot
{
	int offset = -1;  ///< −1: constant (or not in the problem's ordering)
	int tangent = 0;
	int elim = -1;    ///< index among the eliminated variables, or −1
};

class Recovery
{
   public:
	Recovery(SolverContext& ctx, const CovarianceRequest& request) : ctx_(ctx), request_(request)
	{
		const Program& p = ctx.program();
		dim_ = p.kept_dim() + p.elim_dim();
		for (const auto& v : p.kept()) slots_[v.id] = {v.offset, v.tangent, -1};
		for (int l = 0; l < p.num_elim(); l++)
			slots_[p.elim()[l].id] = {p.kept_dim() + p.elim()[l].offset, p.elim()[l].tangent, l};
	}

	CovarianceResult run()
	{
		CovarianceResult out;
		Eigen::VectorXd unused;
		if (!ctx_.eliminator().solve_damped(0.0, 0.0, 0.0, unused))
		{
			out.message = "the normal equations are not positive definite (a free gauge or an unobserved variable)";
			return out;
		}
		if (!request_.gauge.empty()) gauge_solves(out);
		for (const auto& group : request_.groups) out.blocks.push_back(group_block(group, out));
		out.ok = true;
		for (const auto& b : out.blocks) out.ok = out.ok && b.allFinite();
		if (!out.ok) out.message = "a covariance is not finite";
		return out;
	}

   private:
	Slot slot(VariableId v, const Problem& problem) const
	{
		auto it = slots_.find(v);
		if (it != slots_.end()) return it->second;
		Slot s;
		s.tangent = problem.variable(v).manifold->tangent_size();
		return s;
	}

	/** Back-substitution mask: the eliminated variables of `group`. */
	std::vector<char> back_mask(const std::vector<Slot>& slots) const
	{
		std::vector<char> back(static_cast<size_t>(ctx_.program().num_elim()), 0);
		for (const auto& s : slots)
			if (s.elim >= 0) back[s.elim] = 1;
		return back;
	}

	/** G = Σ N (over the whole vector) and the k × k matrices M = (NᵀN)⁻¹, NᵀG. */
	void gauge_solves(CovarianceResult& out)
	{
		int k = 0;
		for (const auto& [v, B] : request_.gauge) k = std::max(k, static_cast<int>(B.cols()));
		N_.setZero(dim_, k);
		Eigen::MatrixXd NtN = Eigen::MatrixXd::Zero(k, k);
		for (const auto& [v, B] : request_.gauge)
		{
			NtN += B.transpose() * B;  // constant variables count too: their displacement is zero
			auto it = slots_.find(v);
			if (it != slots_.end()) N_.middleRows(it->second.offset, B.rows()) = B;
		}
		M_ = NtN.ldlt().solve(Eigen::MatrixXd::Identity(k, k));
		G_.resize(dim_, k);
		for (int c = 0; c < k; c++)
		{
			Eigen::VectorXd x = N_.col(c);
			ctx_.eliminator().solve_factorized(x);
			G_.col(c) = x;
			out.solves++;
		}
		NtG_ = N_.transpose() * G_;
	}

	const Problem& problem_of() const { return ctx_.program().problem(); }

	Eigen::MatrixXd group_block(const std::vector<VariableId>& group, CovarianceResult& out)
	{
		std::vector<Slot> slots;
		std::vector<int> at;  // offset of each variable in the block
		int m = 0;
		for (VariableId v : group)
		{
			slots.push_back(slot(v, problem_of()));
			at.push_back(m);
			m += slots.back().tangent;
		}
		const std::vector<char> back = back_mask(slots);
		Eigen::MatrixXd S = Eigen::MatrixXd::Zero(m, m);
		Eigen::MatrixXd Ng = Eigen::MatrixXd::Zero(m, N_.cols()), Gg = Ng;
		for (size_t i = 0; i < slots.size(); i++)
		{
			if (slots[i].offset < 0)
			{
				// A held variable: no covariance of its own, but the gauge moves it like the others.
				auto it = request_.gauge.find(group[i]);
				if (it != request_.gauge.end()) Ng.middleRows(at[i], slots[i].tangent) = it->second;
				continue;
			}
			for (int j = 0; j < slots[i].tangent; j++)
			{
				Eigen::VectorXd x = Eigen::VectorXd::Zero(dim_);
				x(slots[i].offset + j) = 1.0;
				ctx_.eliminator().solve_factorized(x, back);
				out.solves++;
				for (size_t r = 0; r < slots.size(); r++)
					if (slots[r].offset >= 0)
						S.block(at[r], at[i] + j, slots[r].tangent, 1) = x.segment(slots[r].offset, slots[r].tangent);
			}
			if (N_.cols() > 0)
			{
				Ng.middleRows(at[i], slots[i].tangent) = N_.middleRows(slots[i].offset, slots[i].tangent);
				Gg.middleRows(at[i], slots[i].tangent) = G_.middleRows(slots[i].offset, slots[i].tangent);
			}
		}
		if (N_.cols() > 0)
		{
			// Q Σ Qᵀ restricted to the group, Q = I − N M Nᵀ: Σ − N M Gᵀ − G M Nᵀ + N M (NᵀG) M Nᵀ.
			// A constant variable has Σ = 0 and G = 0 rows: only the last term moves it.
			const Eigen::MatrixXd NM = Ng * M_;
			S += -NM * Gg.transpose() - Gg * NM.transpose() + NM * NtG_ * NM.transpose();
		}
		return 0.5 * (S + S.transpose());
	}

	SolverContext& ctx_;
	const CovarianceRequest& request_;
	std::map<VariableId, Slot> slots_;
	int dim_ = 0;
	Eigen::MatrixXd N_, G_, M_, NtG_;
};
}  // namespace

CovarianceResult recover_covariance(SolverContext& context, const CovarianceRequest& request)
{
	const auto t0 = Clock::now();
	CovarianceResult out = Recovery(context, request).run();
	out.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
	return out;
}
}  // namespace detail

CovarianceResult marginal_covariance(Problem& problem, const CovarianceRequest& request, const SolverOptions& options)
{
	std::string why;
	if (!options.is_valid(&why)) throw std::invalid_argument("SolverOptions: " + why);
	const auto t0 = std::chrono::steady_clock::now();
	detail::SolverContext context(problem, options);
	int dropped = 0;
	context.evaluator().linearize(&dropped);
	context.equations().assemble();
	CovarianceResult out = detail::recover_covariance(context, request);
	out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
	return out;
}
}  // namespace swba
