// swba run: the check that no row's figures are printed as a result when its estimate has left the
// readings behind (internal to the run app). doc/realdata.md explains the choice of statistic.
#pragma once

#include <swba/apps/run.h>

#include <optional>

namespace swba::apps
{
/** How far a row's estimate is from its readings, in its own uncertainty: the median, over the
 * readings whose pose and landmark the row estimates with a covariance, of the normalised innovation
 * squared νᵀS⁻¹ν (ν = z − h(T_k, l): range, yaw and, in 6D, pitch; S = R + the pose's and the
 * landmark's covariance through h), divided by the median of χ² with that many degrees of freedom.
 * Near 1 when the estimate and its covariance fit the readings as the declared noise predicts; the
 * median ignores the outliers a robust estimator leaves out. Empty without pose covariances or
 * landmark estimates (causal rows, covariances off). */
struct ReadingMisfit
{
	double ratio = 0;
	std::size_t readings = 0;  ///< readings predicted
};
std::optional<ReadingMisfit> reading_misfit(const RunRow& row, const io::Rawlog& rawlog,
											const estimators::SlidingWindowOptions& options, bool planar);

/** Above this misfit ratio a row is marked diverged: the median reading is then 4 standard deviations
 * of its innovation or more from the estimate's prediction (a consistent estimate sits near 1; a
 * declared noise half the true one gives at most 4). */
inline constexpr double kDivergedMisfit = 16.0;

/** Marks the rows whose estimate is not finite, or whose reading misfit exceeds kDivergedMisfit,
 * as diverged (RunRow::diverged, with the reason), and adds a note for each. */
void mark_diverged_rows(RunReport& report, const io::Rawlog& rawlog, const estimators::SlidingWindowOptions& options,
						bool planar);
}  // namespace swba::apps
