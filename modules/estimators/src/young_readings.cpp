#include "young_readings.h"

#include <cmath>

namespace swba::estimators::detail
{
namespace
{
/** H1 of the test: twice the declared variance, or the gross readings that weigh as much; then the
 * robust weights do work, and freezing them at marginalisation costs accuracy (doc/realdata.md). The
 * error probabilities make a wrong decision rare either way. */
constexpr double kMisfitVariance = 2;
constexpr double kMisfitAlpha = 1e-3, kMisfitBeta = 1e-3;
}  // namespace

NoiseDecision noise_test(double sum_squares, std::size_t n, int dof, double k, double alpha, double beta)
{
	const double llr = -static_cast<double>(n) * 0.5 * dof * std::log(k) + 0.5 * sum_squares * (1 - 1 / k);
	if (llr >= std::log((1 - beta) / alpha)) return NoiseDecision::Larger;
	if (llr <= std::log(beta / (1 - alpha))) return NoiseDecision::Declared;
	return NoiseDecision::Undecided;
}

YoungReadingRule::YoungReadingRule(const SlidingWindowOptions& o)
	: enabled_(o.robust_loss != RobustLoss::None && o.young_landmark_readings > 0),
	  test_(o.young_readings_test),
	  young_(static_cast<std::size_t>(o.young_landmark_readings))
{
}

void YoungReadingRule::add_readings(const std::vector<std::int32_t>& ids)
{
	for (const std::int32_t id : ids) readings_[id]++;
}

void YoungReadingRule::add_tested(const std::vector<double>& squared_residuals, int dof)
{
	if (!testing()) return;
	for (const double s : squared_residuals) sum_squares_ += s;
	tested_ += squared_residuals.size();
	decision_ = noise_test(sum_squares_, tested_, dof, kMisfitVariance, kMisfitAlpha, kMisfitBeta);
}

bool YoungReadingRule::active() const
{
	return enabled_ && (!test_ || decision_ != NoiseDecision::Declared);
}

bool YoungReadingRule::keeps(const std::vector<std::int32_t>& ids) const
{
	if (ids.empty() || !active()) return false;
	for (const std::int32_t id : ids)
	{
		const auto it = readings_.find(id);
		if (it == readings_.end() || it->second < young_) return true;
	}
	return false;
}
}  // namespace swba::estimators::detail
