#include "prior_only_elimination.h"

#include <swba/factors/linear_prior.h>
#include <swba/linear/marginalization.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <stdexcept>

namespace swba::estimators::detail
{
namespace
{
/** Columns `cols` (scalar indices) of J, in that order. */
Eigen::MatrixXd gather_columns(const Eigen::MatrixXd& J, const std::vector<int>& cols)
{
	Eigen::MatrixXd out(J.rows(), static_cast<Eigen::Index>(cols.size()));
	for (std::size_t c = 0; c < cols.size(); c++) out.col(static_cast<Eigen::Index>(c)) = J.col(cols[c]);
	return out;
}
}  // namespace

bool PriorOnlyElimination::begin(Problem& problem, FactorId prior_factor, const std::vector<VariableId>& vars,
								 const Eigen::MatrixXd& J, const Eigen::VectorXd& e,
								 const std::vector<std::vector<double>>& x_lin, double threshold,
								 const std::function<bool(VariableId)>& eliminable)
{
	active_.clear();
	passive_.clear();
	passive_lin_.clear();
	reduced_factor_ = -1;
	if (vars.size() != x_lin.size()) throw std::invalid_argument("PriorOnlyElimination: one x_lin per variable");

	// Split the prior's scalar columns into prior-only (p) and the rest (a).
	std::vector<int> pcols, acols;
	std::vector<std::shared_ptr<const Manifold>> amanifolds;
	std::vector<std::vector<double>> alin;
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
			for (int c = 0; c < n; c++) pcols.push_back(off + c);
		}
		else
		{
			active_.push_back({vars[i], static_cast<int>(acols.size()), x_lin[i]});
			amanifolds.push_back(var.manifold);
			alin.push_back(x_lin[i]);
			for (int c = 0; c < n; c++) acols.push_back(off + c);
		}
		off += n;
	}
	if (off != J.cols() || e.size() != J.rows()) throw std::invalid_argument("PriorOnlyElimination: J, e and variables disagree");
	if (passive_.empty())
	{
		active_.clear();
		return false;
	}

	// H = JᵀJ and b = −Jᵀe, split into the p and a blocks.
	const Eigen::MatrixXd Jp = gather_columns(J, pcols), Ja = gather_columns(J, acols);
	const Eigen::Index np = Jp.cols(), na = Ja.cols();
	Eigen::MatrixXd Hpp = Eigen::MatrixXd::Zero(np, np);
	Hpp.selfadjointView<Eigen::Lower>().rankUpdate(Jp.transpose());
	Hpp = Eigen::MatrixXd(Hpp.selfadjointView<Eigen::Lower>());
	const Eigen::MatrixXd Hpa = Jp.transpose() * Ja;
	const Eigen::VectorXd bp = -(Jp.transpose() * e), ba = -(Ja.transpose() * e);

	// K = Hpp⁻¹ Hpa, k = Hpp⁻¹ bp: LDLᵀ when Hpp is clearly positive definite (a landmark observed with
	// range and bearing always is), else the thresholded pseudo-inverse swba::marginalize uses.
	Eigen::LDLT<Eigen::MatrixXd> ldlt(Hpp);
	const Eigen::VectorXd D = ldlt.vectorD();
	const double dmax = D.size() ? D.maxCoeff() : 0.0;
	if (ldlt.info() == Eigen::Success && dmax > 0 && D.minCoeff() > threshold * dmax && D.minCoeff() > 0)
	{
		K_ = ldlt.solve(Hpa);
		k_ = ldlt.solve(bp);
	}
	else
	{
		Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(Hpp);
		const Eigen::VectorXd& ev = es.eigenvalues();
		const double lmax = std::max(ev.maxCoeff(), 0.0);
		Eigen::VectorXd inv = Eigen::VectorXd::Zero(np);
		for (Eigen::Index i = 0; i < np; i++)
			if (ev[i] > threshold * lmax && ev[i] > 0) inv[i] = 1.0 / ev[i];
		const Eigen::MatrixXd Hpp_inv = es.eigenvectors() * inv.asDiagonal() * es.eigenvectors().transpose();
		K_ = Hpp_inv * Hpa;
		k_ = Hpp_inv * bp;
	}

	problem.remove_factor(prior_factor);
	for (VariableId v : passive_) problem.set_constant(v, true);
	if (na == 0) return true;
	Eigen::MatrixXd Haa = Eigen::MatrixXd::Zero(na, na);
	Haa.selfadjointView<Eigen::Lower>().rankUpdate(Ja.transpose());
	Haa = Eigen::MatrixXd(Haa.selfadjointView<Eigen::Lower>());
	Haa.noalias() -= Hpa.transpose() * K_;
	const Eigen::VectorXd b_red = ba - Hpa.transpose() * k_;
	std::vector<int> all(static_cast<std::size_t>(na));
	for (Eigen::Index i = 0; i < na; i++) all[static_cast<std::size_t>(i)] = static_cast<int>(i);
	const MarginalizationResult red = marginalize(Haa, b_red, all, {}, threshold);
	if (red.rank > 0)
	{
		std::vector<VariableId> avars;
		for (const auto& a : active_) avars.push_back(a.var);
		reduced_factor_ = problem.add_factor(
			std::make_shared<LinearPriorFactor>(red.J, red.e, std::move(alin), std::move(amanifolds)), std::move(avars));
	}
	return true;
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
}  // namespace swba::estimators::detail
