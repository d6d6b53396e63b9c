// Marginal covariances from the solver's factorisation: the undamped Schur system factorised once,
// then the blocks read from its selected inverse or one solve per tangent coordinate (covariance.h).
#include <swba/core/timing.h>
#include <swba/core/validation.h>
#include <swba/nonlinear/covariance.h>

#include "covariance_recovery.h"
#include "solver_context.h"

#include <Eigen/Dense>
#include <algorithm>
#include <memory>
#include <numeric>
#include <stdexcept>

namespace swba
{
namespace detail
{
namespace
{

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
		std::vector<Group> groups;
		for (const auto& g : request_.groups) groups.push_back(layout(g));
		// The groups the selected inverse cannot serve: solve their columns, several groups at once
		// (one pass through the factor per chunk).
		std::vector<std::size_t> pending = from_selected_inverse(groups);
		std::vector<std::size_t> chunk;
		int columns = 0;
		for (std::size_t k = 0; k < pending.size(); k++)
		{
			chunk.push_back(pending[k]);
			columns += groups[pending[k]].free_columns;
			if (columns >= kColumnsPerChunk || k + 1 == pending.size())
			{
				solve_chunk(groups, chunk, columns, out);
				chunk.clear();
				columns = 0;
			}
		}
		for (std::size_t g = 0; g < groups.size(); g++)
		{
			project_to_gauge(groups[g]);
			out.blocks.push_back(0.5 * (groups[g].S + groups[g].S.transpose()));
		}
		solve_functions(out);
		out.ok = true;
		for (const auto& b : out.blocks) out.ok = out.ok && b.allFinite();
		for (const auto& f : out.functions) out.ok = out.ok && f.allFinite();
		if (!out.ok) out.message = "a covariance is not finite";
		return out;
	}

   private:
	/** Right-hand sides solved together: enough to amortise a pass through a sparse factor, few enough
	 * to keep the block of solutions small. */
	static constexpr int kColumnsPerChunk = 64;

	/** A requested group: its variables' slots, their offsets in the block, the block. */
	struct Group
	{
		std::vector<VariableId> vars;
		std::vector<Slot> slots;
		std::vector<int> at;
		int free_columns = 0;  ///< tangent coordinates of its non-constant variables
		Eigen::MatrixXd S;
	};

	Slot slot(VariableId v) const
	{
		auto it = slots_.find(v);
		if (it != slots_.end()) return it->second;
		Slot s;
		s.tangent = ctx_.program().problem().variable(v).manifold->tangent_size();
		return s;
	}

	Group layout(const std::vector<VariableId>& vars) const
	{
		Group g;
		g.vars = vars;
		int m = 0;
		for (VariableId v : vars)
		{
			g.slots.push_back(slot(v));
			g.at.push_back(m);
			m += g.slots.back().tangent;
			if (g.slots.back().offset >= 0) g.free_columns += g.slots.back().tangent;
		}
		g.S = Eigen::MatrixXd::Zero(m, m);
		return g;
	}

	/** Fills the groups over kept variables only from S⁻¹ on the factor's pattern, when they ask for
	 * more columns than one chunk of solves and the pass over the factor is estimated cheaper than
	 * their solves; returns the indices of the groups left to solve. */
	std::vector<std::size_t> from_selected_inverse(std::vector<Group>& groups) const
	{
		int kept_columns = 0;
		for (const Group& g : groups)
			if (only_kept(g)) kept_columns += g.free_columns;
		std::unique_ptr<SelectedInverse> inverse;
		if (kept_columns > kColumnsPerChunk)
		{
			try
			{
				inverse = ctx_.eliminator().selected_inverse(kept_columns);
			}
			catch (const std::invalid_argument&)
			{
				inverse.reset();  // not a factor's pattern after all: the solves still are exact
			}
		}
		std::vector<std::size_t> pending;
		for (std::size_t g = 0; g < groups.size(); g++)
			if (!inverse || !only_kept(groups[g]) || !fill_from(*inverse, groups[g])) pending.push_back(g);
		return pending;
	}

	static bool only_kept(const Group& g)
	{
		return std::all_of(g.slots.begin(), g.slots.end(), [](const Slot& s) { return s.elim < 0; });
	}

	/** The group's block from the selected inverse; false (block untouched) if an entry is outside the
	 * factor's pattern (variables that share no factor). */
	static bool fill_from(const SelectedInverse& inverse, Group& g)
	{
		Eigen::MatrixXd S = Eigen::MatrixXd::Zero(g.S.rows(), g.S.cols());
		for (std::size_t r = 0; r < g.slots.size(); r++)
			for (std::size_t c = 0; c < g.slots.size(); c++)
			{
				const Slot &a = g.slots[r], &b = g.slots[c];
				if (a.offset < 0 || b.offset < 0) continue;
				for (int i = 0; i < a.tangent; i++)
					for (int j = 0; j < b.tangent; j++)
						if (!inverse.find(a.offset + i, b.offset + j, S(g.at[r] + i, g.at[c] + j))) return false;
			}
		g.S = S;
		return true;
	}

	/** Solves the unit columns of the non-constant variables of the groups `chunk` and fills their
	 * blocks: column j of Σ restricted to each group's rows. */
	void solve_chunk(std::vector<Group>& groups, const std::vector<std::size_t>& chunk, int columns,
					 CovarianceResult& out)
	{
		if (columns == 0) return;
		Eigen::MatrixXd X = Eigen::MatrixXd::Zero(dim_, columns);
		std::vector<char> back(static_cast<std::size_t>(ctx_.program().num_elim()), 0);
		int c = 0;
		for (std::size_t g : chunk)
			for (const Slot& s : groups[g].slots)
			{
				if (s.elim >= 0) back[static_cast<std::size_t>(s.elim)] = 1;
				if (s.offset < 0) continue;
				for (int j = 0; j < s.tangent; j++) X(s.offset + j, c++) = 1.0;
			}
		ctx_.eliminator().solve_factorized(X, back);
		out.solves += columns;
		c = 0;
		for (std::size_t g : chunk)
		{
			Group& G = groups[g];
			for (std::size_t i = 0; i < G.slots.size(); i++)
			{
				if (G.slots[i].offset < 0) continue;
				for (int j = 0; j < G.slots[i].tangent; j++, c++)
					for (std::size_t r = 0; r < G.slots.size(); r++)
						if (G.slots[r].offset >= 0)
							G.S.block(G.at[r], G.at[i] + j, G.slots[r].tangent, 1) =
								X.block(G.slots[r].offset, c, G.slots[r].tangent, 1);
			}
		}
	}

	/** Rows of a function (checks that every block has them and its variable's tangent columns). */
	int function_rows(const LinearFunction& f) const
	{
		const int m = f.empty() ? 0 : static_cast<int>(f.begin()->second.rows());
		for (const auto& [v, A] : f)
			if (A.rows() != m || A.cols() != slot(v).tangent)
				throw std::invalid_argument("CovarianceRequest: a function's block has the wrong size");
		return m;
	}

	/** The functions' covariances A Σ Aᵀ (A Q Σ Qᵀ Aᵀ with gauge directions): the columns Σ Aᵀ of all
	 * of them in one pass through the factor. */
	void solve_functions(CovarianceResult& out)
	{
		std::vector<int> rows;
		for (const auto& f : request_.functions) rows.push_back(function_rows(f));
		Eigen::MatrixXd X = Eigen::MatrixXd::Zero(dim_, std::accumulate(rows.begin(), rows.end(), 0));
		std::vector<char> back(static_cast<std::size_t>(ctx_.program().num_elim()), 0);
		for (std::size_t i = 0, c = 0; i < rows.size(); c += static_cast<std::size_t>(rows[i++]))
			for (const auto& [v, A] : request_.functions[i])
			{
				const Slot s = slot(v);
				if (s.offset < 0) continue;
				if (s.elim >= 0) back[static_cast<std::size_t>(s.elim)] = 1;
				X.block(s.offset, static_cast<Eigen::Index>(c), s.tangent, rows[i]) = A.transpose();
			}
		if (X.cols() > 0) ctx_.eliminator().solve_factorized(X, back);
		out.solves += static_cast<int>(X.cols());
		for (std::size_t i = 0, c = 0; i < rows.size(); c += static_cast<std::size_t>(rows[i++]))
		{
			const Eigen::Index m = rows[i];
			Eigen::MatrixXd S = Eigen::MatrixXd::Zero(m, m), Nf = Eigen::MatrixXd::Zero(m, N_.cols()), Gf = Nf;
			for (const auto& [v, A] : request_.functions[i])
			{
				const Slot s = slot(v);
				if (s.offset >= 0)
				{
					S += A * X.block(s.offset, static_cast<Eigen::Index>(c), s.tangent, m);
					if (N_.cols() > 0) Nf += A * N_.middleRows(s.offset, s.tangent);
					if (N_.cols() > 0) Gf += A * G_.middleRows(s.offset, s.tangent);
				}
				else if (auto it = request_.gauge.find(v); it != request_.gauge.end())
					Nf += A * it->second;
			}
			if (N_.cols() > 0) S += gauge_correction(Nf, Gf);
			out.functions.push_back(0.5 * (S + S.transpose()));
		}
	}

	/** G = Σ N (over the whole vector) and the k × k matrices M = (NᵀN)⁺, NᵀG. */
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
		// Pseudo-inverse: a planar model's off-plane motions are zero columns.
		M_ = NtN.completeOrthogonalDecomposition().pseudoInverse();
		G_ = N_;
		ctx_.eliminator().solve_factorized(G_);
		out.solves += k;
		NtG_ = N_.transpose() * G_;
	}

	/** Q Σ Qᵀ restricted to the group, Q = I − N M Nᵀ: Σ − N M Gᵀ − G M Nᵀ + N M (NᵀG) M Nᵀ. A constant
	 * variable has Σ = 0 and G = 0 rows: only the last term moves it. Nothing without gauge directions. */
	void project_to_gauge(Group& g) const
	{
		if (N_.cols() == 0) return;
		Eigen::MatrixXd Ng = Eigen::MatrixXd::Zero(g.S.rows(), N_.cols()), Gg = Ng;
		for (std::size_t i = 0; i < g.slots.size(); i++)
		{
			const int t = g.slots[i].tangent;
			if (g.slots[i].offset >= 0)
			{
				Ng.middleRows(g.at[i], t) = N_.middleRows(g.slots[i].offset, t);
				Gg.middleRows(g.at[i], t) = G_.middleRows(g.slots[i].offset, t);
			}
			else if (auto it = request_.gauge.find(g.vars[i]); it != request_.gauge.end())
				Ng.middleRows(g.at[i], t) = it->second;  // a held variable: moved by the gauge like the others
		}
		g.S += gauge_correction(Ng, Gg);
	}

	/** Q Σ Qᵀ − Σ for the rows Ng = A N, Gg = A G of a block (see project_to_gauge). */
	Eigen::MatrixXd gauge_correction(const Eigen::MatrixXd& Ng, const Eigen::MatrixXd& Gg) const
	{
		const Eigen::MatrixXd NM = Ng * M_;
		return -NM * Gg.transpose() - Gg * NM.transpose() + NM * NtG_ * NM.transpose();
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
	const auto t0 = SteadyClock::now();
	CovarianceResult out = Recovery(context, request).run();
	out.seconds = seconds_since(t0);
	return out;
}
}  // namespace detail

CovarianceResult marginal_covariance(Problem& problem, const CovarianceRequest& request, const SolverOptions& options)
{
	validate_with_prefix(options, "SolverOptions: ");
	const auto t0 = SteadyClock::now();
	detail::SolverContext context(problem, options);
	int dropped = 0;
	context.evaluator().linearize(&dropped);
	context.equations().assemble();
	CovarianceResult out = detail::recover_covariance(context, request);
	out.seconds = seconds_since(t0);
	return out;
}
}  // namespace swba
