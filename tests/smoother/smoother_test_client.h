// A SmootherClient for the smoother tests: prior-only handling by a predicate, fixed variables leaving
// with the oldest state, and a record of the marginalisations and of the states that left.
#pragma once

#include <swba/smoother/fixed_lag_smoother.h>

#include <functional>
#include <set>
#include <vector>

namespace swba::test
{
struct RecordingClient : smoother::SmootherClient
{
	std::function<smoother::PriorOnly(VariableId)> handling;  ///< empty: Keep
	std::set<VariableId> also;                                ///< variables leaving with the oldest state
	std::vector<smoother::MarginalizationSummary> marginalizations;
	std::vector<smoother::LinearState> left_states;

	smoother::PriorOnly prior_only(VariableId v) const override
	{
		return handling ? handling(v) : smoother::PriorOnly::Keep;
	}
	std::set<VariableId> leaving(const smoother::TimedState&) override { return also; }
	void marginalized(const smoother::TimedState&, const smoother::MarginalizationSummary& m) override
	{
		marginalizations.push_back(m);
	}
	void left(const smoother::TimedState& s, const std::vector<double>& value) override
	{
		left_states.push_back({s.time, s.var, value});
	}
};
}  // namespace swba::test
