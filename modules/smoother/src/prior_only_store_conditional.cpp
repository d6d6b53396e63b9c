// PriorOnlyStore::conditional (prior_only_store.h): the stored conditional of some of its variables,
// for a covariance through it (linear_conditional.h).
#include "prior_only_store.h"

namespace swba::smoother::detail
{
LinearConditional PriorOnlyStore::conditional(const std::vector<VariableId>& vars) const
{
	LinearConditional c;
	c.vars = vars;
	for (VariableId v : vars) c.dims.push_back(static_cast<int>(rows_of({v}).size()));
	const std::vector<int> rows = rows_of(vars);
	c.covariance = covariance_columns(rows)(rows, Eigen::all);
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
