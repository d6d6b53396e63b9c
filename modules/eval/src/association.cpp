// Time-stamp association as evo's sync.associate_trajectories (nearest stamp, first on ties).
#include "swba/eval/association.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace swba::eval
{
namespace
{
/** For each stamp of `shorter`, the index of the first element of `longer_shifted` at the smallest
 * |longer_shifted[j] − s| (numpy's argmin semantics), kept when that distance ≤ max_diff. `longer_shifted`
 * is sorted (non-decreasing), which lets a binary search replace evo's linear scan without changing
 * the result. */
void match(const std::vector<double>& shorter, const std::vector<double>& longer_shifted, double max_diff,
		   std::vector<std::size_t>& short_ids, std::vector<std::size_t>& long_ids)
{
	const std::size_t n = longer_shifted.size();
	if (n == 0) return;
	for (std::size_t i = 0; i < shorter.size(); i++)
	{
		const double s = shorter[i];
		const std::size_t k =
			static_cast<std::size_t>(std::lower_bound(longer_shifted.begin(), longer_shifted.end(), s) - longer_shifted.begin());
		std::size_t best = n;
		double dbest = 0;
		if (k < n)
		{
			best = k;
			dbest = std::abs(longer_shifted[k] - s);
		}
		if (k > 0)
		{
			const double d = std::abs(longer_shifted[k - 1] - s);
			if (best == n || d <= dbest)
			{
				best = k - 1;
				dbest = d;
				// Earlier stamps equal (after rounding) in distance win, as argmin returns the first.
				while (best > 0 && std::abs(longer_shifted[best - 1] - s) == dbest) best--;
			}
		}
		if (dbest <= max_diff)
		{
			short_ids.push_back(i);
			long_ids.push_back(best);
		}
	}
}
}  // namespace

Association associate(const Trajectory& ref, const Trajectory& est, const AssociationOptions& options)
{
	Association a;
	const bool est_longer = est.stamps.size() > ref.stamps.size();
	const Trajectory& longer = est_longer ? est : ref;
	const Trajectory& shorter = est_longer ? ref : est;
	// evo adds the offset to the longer trajectory's stamps: +offset if it is the estimate, −offset if
	// it is the reference.
	const double offset = est_longer ? options.t_offset : -options.t_offset;
	std::vector<double> shifted(longer.stamps);
	for (double& t : shifted) t += offset;
	if (est_longer)
		match(shorter.stamps, shifted, options.t_max_diff, a.ref_ids, a.est_ids);
	else
		match(shorter.stamps, shifted, options.t_max_diff, a.est_ids, a.ref_ids);
	return a;
}

void associate_trajectories(const Trajectory& ref, const Trajectory& est, const AssociationOptions& options,
							Trajectory& ref_out, Trajectory& est_out)
{
	const Association a = associate(ref, est, options);
	if (a.size() == 0)
	{
		std::ostringstream ss;
		ss << "found no matching time stamps between the reference (" << ref.size() << " poses";
		if (!ref.empty()) ss << ", t = " << ref.stamps.front() << " .. " << ref.stamps.back();
		ss << ") and the estimate (" << est.size() << " poses";
		if (!est.empty()) ss << ", t = " << est.stamps.front() << " .. " << est.stamps.back();
		ss << ") with max. time diff " << options.t_max_diff << " s and time offset " << options.t_offset << " s";
		throw std::runtime_error(ss.str());
	}
	ref_out = ref.subset(a.ref_ids);
	est_out = est.subset(a.est_ids);
}
}  // namespace swba::eval
