/** \file young_readings.h
 * (private to the estimators module) The window's rule for the readings of young landmarks
 * (SlidingWindowOptions::young_landmark_readings and young_readings): a pose that holds one stays
 * re-linearised, so the reading's robust weight is not frozen while its landmark is still fitted to it. */
#pragma once

#include <swba/estimators/sliding_window.h>

#include <cstddef>
#include <cstdint>
#include <map>
#include <vector>

namespace swba::estimators::detail
{
/** What a sequential test between the declared noise and a larger one has decided so far. */
enum class NoiseDecision
{
	Undecided,
	Declared,  ///< H0: the whitened squared residuals are χ²_dof, the declared noise
	Larger     ///< H1: they are k·χ²_dof, a variance k times the declared one
};

/** Wald's sequential probability ratio test of H0 against H1 on `n` readings of `dof` rows whose whitened
 * squared residuals sum to `sum_squares`, with error probabilities alpha (H1 chosen under H0) and beta:
 * the log likelihood ratio n·(dof/2)·(−ln k) + (sum_squares/2)·(1 − 1/k) against ln((1 − beta)/alpha) and
 * ln(beta/(1 − alpha)). A gross reading weighs for H1 at once; under H0 the ratio falls by about
 * 0.1·dof per reading for k = 2, so a few dozen readings decide. */
NoiseDecision noise_test(double sum_squares, std::size_t n, int dof, double k, double alpha, double beta);

class YoungReadingRule
{
   public:
	explicit YoungReadingRule(const SlidingWindowOptions& options);
	/** A step's readings, by the landmark ID each was given. */
	void add_readings(const std::vector<std::int32_t>& ids);
	/** Whether the test still needs evidence (noise_test undecided). */
	bool testing() const { return enabled_ && test_ && decision_ == NoiseDecision::Undecided; }
	/** Evidence for the test: the whitened squared residuals of readings (`dof` rows each) entering the
	 * marginal prior, at the estimate they enter with (the one their frozen weights come from). */
	void add_tested(const std::vector<double>& squared_residuals, int dof);
	/** Whether a pose whose readings were given `ids` stays re-linearised now. */
	bool keeps(const std::vector<std::int32_t>& ids) const;

   private:
	/** Whether the rule runs: never without a robust loss or with N = 0; else always, or with the test
	 * until noise_test decides that the readings tested so far fit their declared noise (for good). */
	bool active() const;

	bool enabled_, test_;
	std::size_t young_;  ///< N: a landmark given fewer readings is young
	NoiseDecision decision_ = NoiseDecision::Undecided;
	std::size_t tested_ = 0;
	double sum_squares_ = 0;
	std::map<std::int32_t, std::size_t> readings_;  ///< readings given to each landmark so far
};
}  // namespace swba::estimators::detail
