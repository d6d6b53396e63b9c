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
	// Column j's off-diagonal rows R_j, scattered: where[i] = index of row i in R_j, else −1. Every
	// Z_ik with i, k ∈ R_j lies in column min(i, k), so one scan of each column k ∈ R_j gives both
	// Σ_k Z_ik L_kj (i > k) and its mirror term Z_ki L_ij for s_k.
	std::vector<int> where(static_cast<std::size_t>(n), -1);
	std::vector<double> s;
	for (int j = n - 1; j >= 0; j--)
	{
		const int p0 = col_begin[j] + 1, m = col_begin[j + 1] - p0;
		for (int t = 0; t < m; t++) where[static_cast<std::size_t>(rows[p0 + t])] = t;
		s.assign(static_cast<std::size_t>(m), 0.0);
		for (int t = 0; t < m; t++)
		{
			const int k = rows[p0 + t];
			const double lkj = values[p0 + t];
			s[static_cast<std::size_t>(t)] += z_[static_cast<std::size_t>(col_begin[k])] * lkj;
			int hits = 0;
			for (int u = col_begin[k] + 1; u < col_begin[k + 1]; u++)
			{
				const int w = where[static_cast<std::size_t>(rows[u])];
				if (w < 0) continue;
				s[static_cast<std::size_t>(w)] += z_[static_cast<std::size_t>(u)] * lkj;
				s[static_cast<std::size_t>(t)] += z_[static_cast<std::size_t>(u)] * values[p0 + w];
				hits++;
			}
			if (hits != m - t - 1)
				throw std::invalid_argument("SelectedInverse: column " + std::to_string(k) +
											" misses a fill entry of column " + std::to_string(j));
		}
		const double ljj = values[p0 - 1];
		double diag = 1.0 / ljj;
		for (int t = 0; t < m; t++)
		{
			z_[static_cast<std::size_t>(p0 + t)] = -s[static_cast<std::size_t>(t)] / ljj;
			diag -= z_[static_cast<std::size_t>(p0 + t)] * values[p0 + t];
			where[static_cast<std::size_t>(rows[p0 + t])] = -1;
		}
		z_[static_cast<std::size_t>(p0 - 1)] = diag / ljj;
	}
}

double SelectedInverse::work(int n, const int* col_begin, const int* rows)
{
	double w = 0;
	for (int j = 0; j < n; j++)
		for (int q = col_begin[j] + 1; q < col_begin[j + 1]; q++) w += col_begin[rows[q] + 1] - col_begin[rows[q]];
	return w;
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
