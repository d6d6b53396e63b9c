// PriorOnlyStore::conditional (prior_only_store.h): the stored conditional of some of its variables,
// for a covariance through it (linear_conditional.h).
#include "prior_only_store.h"

#include <algorithm>

namespace swba::smoother::detail
{
LinearConditional PriorOnlyStore::conditional(const std::vector<VariableId>& vars) const
{
	LinearConditional c;
	c.vars = vars;
	for (VariableId v : vars) c.dims.push_back(static_cast<int>(rows_of({v}).size()));
	const std::vector<int> rows = rows_of(vars);
	// C over those rows only (pending updates included): covariance_columns() would form their columns
	// over every stored row, O(stored · rows · pending) where this is O(rows² · pending).
	c.covariance.resize(static_cast<Eigen::Index>(rows.size()), static_cast<Eigen::Index>(rows.size()));
	for (std::size_t j = 0; j < rows.size(); j++)
		for (std::size_t i = 0; i < rows.size(); i++)
			c.covariance(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) =
				C_(std::max(rows[i], rows[j]), std::min(rows[i], rows[j]));  // the lower triangle is kept
	if (pending_ > 0)
	{
		const Eigen::MatrixXd P = P_(rows, Eigen::seqN(0, pending_));
		c.covariance.noalias() += P * sign_.head(pending_).asDiagonal() * P.transpose();
	}
	Eigen::Index cols = 0;
	for (const auto& [w, Kw] : K_)
	{
		c.sep.push_back(w);
		c.sep_dims.push_back(static_cast<int>(Kw.cols()));
		cols += Kw.cols();
	}
	c.K.resize(static_cast<Eigen::Index>(rows.size()), cols);
	Eigen::Index off = 0;
	for (const auto& [w, Kw] : K_)
	{
		c.K.middleCols(off, Kw.cols()) = Kw(rows, Eigen::all);
		off += Kw.cols();
	}
	return c;
}
}  // namespace swba::smoother::detail
