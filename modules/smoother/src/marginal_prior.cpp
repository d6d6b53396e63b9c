#include <swba/smoother/marginal_prior.h>

#include <swba/factors/linear_prior.h>

#include <algorithm>
#include <memory>
#include <stdexcept>

namespace swba::smoother
{
int MarginalPrior::index_of(VariableId v) const
{
	auto it = std::find(vars_.begin(), vars_.end(), v);
	return it == vars_.end() ? -1 : static_cast<int>(it - vars_.begin());
}

MarginalPrior::Partition MarginalPrior::partition(const Problem& problem,
												  const std::function<bool(VariableId)>& in_first) const
{
	Partition p;
	int off = 0;
	for (std::size_t i = 0; i < vars_.size(); i++)
	{
		const int n = problem.variable(vars_[i]).manifold->tangent_size();
		const bool first = in_first(vars_[i]);
		(first ? p.first : p.second).push_back(i);
		for (int c = 0; c < n; c++) (first ? p.first_columns : p.second_columns).push_back(off + c);
		off += n;
	}
	const Eigen::Index cols = has_information_ ? H_.cols() : J_.cols();
	if (off != cols) throw std::invalid_argument("MarginalPrior::partition: the prior's size and variables disagree");
	return p;
}

int MarginalPrior::column_of(const Problem& problem, int index) const
{
	int off = 0;
	for (int i = 0; i < index; i++) off += problem.variable(vars_[i]).manifold->tangent_size();
	return off;
}

void MarginalPrior::reset(Problem& problem, std::vector<VariableId> vars, MarginalizationResult m,
						  std::vector<std::vector<double>> x_lin)
{
	if (m.rank == 0)
	{
		clear();
		return;
	}
	if (x_lin.empty())
		for (VariableId v : vars) x_lin.push_back(problem.variable(v).value);
	if (x_lin.size() != vars.size()) throw std::invalid_argument("MarginalPrior::reset: one x_lin per variable");
	// m is the quadratic in δ = x ⊟ x_cur; stored in d = x ⊟ x_lin, δ = d − (x_cur ⊟ x_lin) to first order:
	// e ← e − J s and b ← b + H s with s = x_cur ⊟ x_lin (H is unchanged).
	Eigen::VectorXd shift(m.J.cols());
	int off = 0;
	for (std::size_t i = 0; i < vars.size(); i++)
	{
		const auto& var = problem.variable(vars[i]);
		var.manifold->minus(var.value.data(), x_lin[i].data(), shift.data() + off);
		off += var.manifold->tangent_size();
	}
	if (off != m.J.cols()) throw std::invalid_argument("MarginalPrior::reset: J and the variables' sizes disagree");
	m.e -= m.J * shift;
	m.b += m.H * shift;
	assign(problem, std::move(vars), std::move(m), std::move(x_lin));
}

void MarginalPrior::assign(Problem& problem, std::vector<VariableId> vars, MarginalizationResult m,
						   std::vector<std::vector<double>> x_lin)
{
	if (m.rank == 0 || vars.empty())
	{
		uninstall(problem);
		clear();
		return;
	}
	if (x_lin.size() != vars.size()) throw std::invalid_argument("MarginalPrior::assign: one x_lin per variable");
	if (installed()) problem.remove_factor(factor_);
	factor_ = -1;
	vars_ = std::move(vars);
	e_ = std::move(m.e);
	J_ = std::move(m.J);
	x_lin_ = std::move(x_lin);
	b_ = std::move(m.b);
	H_ = std::move(m.H);
	has_information_ = true;
	install(problem);
}

void MarginalPrior::append_rows(Problem& problem, const std::vector<VariableId>& new_vars,
								const std::vector<std::vector<double>>& new_x_lin, const Eigen::MatrixXd& J_rows,
								const Eigen::VectorXd& e_rows)
{
	if (new_vars.size() != new_x_lin.size() || J_rows.rows() != e_rows.size())
		throw std::invalid_argument("MarginalPrior::append_rows: sizes disagree");
	if (!has_information_ && J_.rows() > 0)
	{
		H_ = J_.transpose() * J_;
		b_ = -(J_.transpose() * e_);
	}
	const Eigen::Index n0 = J_.cols();
	for (std::size_t i = 0; i < new_vars.size(); i++)
	{
		if (index_of(new_vars[i]) >= 0) throw std::invalid_argument("MarginalPrior::append_rows: variable already in");
		vars_.push_back(new_vars[i]);
		x_lin_.push_back(new_x_lin[i]);
	}
	const Eigen::Index n = J_rows.cols();
	if (n < n0) throw std::invalid_argument("MarginalPrior::append_rows: fewer columns than the prior");
	Eigen::MatrixXd J = Eigen::MatrixXd::Zero(J_.rows() + J_rows.rows(), n);
	J.topLeftCorner(J_.rows(), n0) = J_;
	J.bottomRows(J_rows.rows()) = J_rows;
	Eigen::VectorXd e(e_.size() + e_rows.size());
	e << e_, e_rows;
	Eigen::MatrixXd H = Eigen::MatrixXd::Zero(n, n);
	Eigen::VectorXd b = Eigen::VectorXd::Zero(n);
	if (n0 > 0)
	{
		H.topLeftCorner(n0, n0) = H_;
		b.head(n0) = b_;
	}
	H.noalias() += J_rows.transpose() * J_rows;
	b.noalias() -= J_rows.transpose() * e_rows;
	J_ = std::move(J);
	e_ = std::move(e);
	H_ = std::move(H);
	b_ = std::move(b);
	has_information_ = true;
	install(problem);
}

void MarginalPrior::clear() { *this = MarginalPrior(); }

void MarginalPrior::uninstall(Problem& problem)
{
	if (installed()) problem.remove_factor(factor_);
	factor_ = -1;
}

void MarginalPrior::install(Problem& problem)
{
	uninstall(problem);
	if (vars_.empty() || J_.rows() == 0)
	{
		clear();
		return;
	}
	std::vector<std::shared_ptr<const Manifold>> manifolds;
	for (VariableId v : vars_) manifolds.push_back(problem.variable(v).manifold);
	factor_ = problem.add_factor(std::make_shared<LinearPriorFactor>(J_, e_, x_lin_, manifolds), vars_);
}

int MarginalPrior::add_variable(const Problem& problem, VariableId v)
{
	const int idx = index_of(v);
	if (idx >= 0) return idx;
	const int n = problem.variable(v).manifold->tangent_size();
	Eigen::MatrixXd J(J_.rows(), J_.cols() + n);
	J << J_, Eigen::MatrixXd::Zero(J_.rows(), n);
	if (has_information_)
	{
		// The new columns of J are zero: so are the new rows and columns of H and entries of b.
		const Eigen::Index m = H_.rows();
		H_.conservativeResize(m + n, m + n);
		H_.rightCols(n).setZero();
		H_.bottomRows(n).setZero();
		b_.conservativeResize(m + n);
		b_.tail(n).setZero();
	}
	J_ = J;
	vars_.push_back(v);
	x_lin_.push_back(problem.variable(v).value);
	return static_cast<int>(vars_.size()) - 1;
}

void MarginalPrior::refresh_information(int c0, int n)
{
	if (!has_information_) return;
	const Eigen::MatrixXd cols = J_.transpose() * J_.middleCols(c0, n);
	H_.middleCols(c0, n) = cols;
	H_.middleRows(c0, n) = cols.transpose();
	b_.segment(c0, n) = -(J_.middleCols(c0, n).transpose() * e_);
}

std::vector<std::pair<VariableId, Eigen::MatrixXd>> change_columns(const VariableChange& change,
																   const Eigen::MatrixXd& M_old)
{
	if (M_old.cols() != change.D.rows() || change.D.cols() != change.H_new.rows())
		throw std::invalid_argument("change_columns: the change's sizes disagree");
	const Eigen::MatrixXd MD = M_old * change.D;
	std::vector<std::pair<VariableId, Eigen::MatrixXd>> out{{change.new_var, MD * change.H_new}};
	for (const auto& [y, H] : change.H_others)
	{
		if (H.rows() != change.D.cols()) throw std::invalid_argument("change_columns: the change's sizes disagree");
		out.emplace_back(y, MD * H);
	}
	return out;
}

void MarginalPrior::change_variable(const Problem& problem, const VariableChange& change)
{
	const int idx = index_of(change.old_var);
	const int col = column_of(problem, idx);
	const int n_old = problem.variable(change.old_var).manifold->tangent_size();
	const auto blocks = change_columns(change, J_.middleCols(col, n_old));
	// The y_i (already in the prior) gain their share first, then old_var's columns become new_var's.
	std::vector<std::pair<int, int>> changed;
	for (std::size_t i = 1; i < blocks.size(); i++)
	{
		const int c = column_of(problem, index_of(blocks[i].first));
		J_.middleCols(c, blocks[i].second.cols()) += blocks[i].second;
		changed.push_back({c, static_cast<int>(blocks[i].second.cols())});
	}
	const Eigen::Index n_new = blocks[0].second.cols();
	if (n_new == n_old)
	{
		J_.middleCols(col, n_old) = blocks[0].second;
		for (const auto& [c, n] : changed) refresh_information(c, n);
		refresh_information(col, n_old);
	}
	else  // the column layout changes: H and b anew
	{
		Eigen::MatrixXd J(J_.rows(), J_.cols() - n_old + n_new);
		J << J_.leftCols(col), blocks[0].second, J_.rightCols(J_.cols() - col - n_old);
		J_ = std::move(J);
		if (has_information_)
		{
			H_ = J_.transpose() * J_;
			b_ = -(J_.transpose() * e_);
		}
	}
	vars_[static_cast<std::size_t>(idx)] = change.new_var;
	x_lin_[static_cast<std::size_t>(idx)] = change.new_x_lin;
}
}  // namespace swba::smoother
