// Internal: a map (i, j) → block index for the block patterns of the normal equations.
#pragma once

#include <map>
#include <utility>
#include <vector>

namespace swba::detail
{
/** (i, j) → block index, −1 if absent: a dense table while rows·cols is small (a window's system,
 * rebuilt every step), an ordered map otherwise (BAL: thousands of cameras). */
class BlockIndex
{
   public:
	BlockIndex(int rows, int cols) : cols_(cols)
	{
		if (static_cast<long long>(rows) * cols <= kDenseMaxEntries)
			dense_.assign(static_cast<size_t>(rows) * static_cast<size_t>(cols), -1);
	}
	int find(int i, int j) const
	{
		if (!dense_.empty()) return dense_[static_cast<size_t>(i) * cols_ + j];
		const auto it = map_.find({i, j});
		return it == map_.end() ? -1 : it->second;
	}
	void set(int i, int j, int index)
	{
		if (!dense_.empty())
			dense_[static_cast<size_t>(i) * cols_ + j] = index;
		else
			map_[{i, j}] = index;
	}

   private:
	static constexpr long long kDenseMaxEntries = 1 << 20;
	size_t cols_;
	std::vector<int> dense_;
	std::map<std::pair<int, int>, int> map_;
};
}  // namespace swba::detail
