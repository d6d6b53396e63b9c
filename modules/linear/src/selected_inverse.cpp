#include <swba/linear/selected_inverse.h>

#include <algorithm>
#include <stdexcept>
#include <string>

namespace swba
{
namespace
{
void check_column(int j, const int* rows, int begin, int end)
{
	if (begin >= end || rows[begin] != j)
		throw std::invalid_argument("SelectedInverse: column " + std::to_string(j) + " does not start with its diagonal");
	for (int q = begin + 1; q < end; q++)
		if (rows[q] <= rows[q - 1])
			throw std::invalid_argument("SelectedInverse: the rows of column " + std::to_string(j) +
										" are not strictly ascending");
}
}  // namespace

SelectedInverse::SelectedInverse(int n, const int* col_begin, const int* rows, const double* values, const int* perm)
	: col_begin_(col_begin, col_begin + n + 1), rows_(rows, rows + col_begin[n]), iperm_(static_cast<std::size_t>(n))
{
	for (int k = 0; k < n; k++) iperm_[static_cast<std::size_t>(perm ? perm[k] : k)] = k;
	for (int j = 0; j < n; j++) check_column(j, rows, col_begin[j], col_begin[j + 1]);
	z_.assign(rows_.size(), 0.0);
	for (int j = n - 1; j >= 0; j--)
	{
		const int p0 = col_begin[j], p1 = col_begin[j + 1];
		const double ljj = values[p0];
		for (int q = p0 + 1; q < p1; q++)
		{
			const int i = rows[q];
			double s = 0;
			for (int t = p0 + 1; t < p1; t++)
			{
				const int k = rows[t];
				const long z = position(std::max(i, k), std::min(i, k));
				if (z < 0)
					throw std::invalid_argument("SelectedInverse: the pattern misses the fill entry (" +
												std::to_string(std::max(i, k)) + ", " +
												std::to_string(std::min(i, k)) + ")");
				s += z_[static_cast<std::size_t>(z)] * values[t];
			}
			z_[static_cast<std::size_t>(q)] = -s / ljj;
		}
		double s = 0;
		for (int t = p0 + 1; t < p1; t++) s += z_[static_cast<std::size_t>(t)] * values[t];
		z_[static_cast<std::size_t>(p0)] = (1.0 / ljj - s) / ljj;
	}
}

long SelectedInverse::position(int a, int b) const
{
	const auto begin = rows_.begin() + col_begin_[static_cast<std::size_t>(b)];
	const auto end = rows_.begin() + col_begin_[static_cast<std::size_t>(b) + 1];
	const auto it = std::lower_bound(begin, end, a);
	return it != end && *it == a ? static_cast<long>(it - rows_.begin()) : -1;
}

bool SelectedInverse::find(int r, int c, double& value) const
{
	if (r < 0 || c < 0 || r >= dim() || c >= dim()) return false;
	const int a = iperm_[static_cast<std::size_t>(r)], b = iperm_[static_cast<std::size_t>(c)];
	const long z = position(std::max(a, b), std::min(a, b));
	if (z < 0) return false;
	value = z_[static_cast<std::size_t>(z)];
	return true;
}
}  // namespace swba
