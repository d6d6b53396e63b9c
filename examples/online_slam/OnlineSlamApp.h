/** \file OnlineSlamApp.h
 * An MRPT application embedding swba's sliding-window estimator in an online loop: action
 * collections and sensory frames are read one pair at a time (as they would arrive from a robot)
 * and handed to swba::estimators::MrptSlidingWindow; after each step the current pose, the window and
 * the landmark map are available. Prints a progress line (with the landmark each reading of the step
 * was associated with) every `print_every` steps, the final pose and the landmarks' covariances;
 * optionally writes the online and lagged trajectories as TUM files. */
#pragma once

#include <swba/estimators/mrpt_adapter.h>

#include <cstddef>
#include <cstdint>
#include <string>

class OnlineSlamApp
{
   public:
	/** Parses the command line. Returns false after printing the usage for --help. Throws
	 * std::invalid_argument with a one-line reason on bad arguments, std::runtime_error on a bad
	 * --config file. */
	bool initialize(int argc, char** argv);
	/** Reads the rawlog and feeds the estimator pair by pair. Throws std::runtime_error naming the
	 * rawlog (and the entry) when it cannot be read, is corrupt or holds no step,
	 * std::invalid_argument on invalid data. */
	void run();

	/** The estimator's options (after initialize()). */
	swba::estimators::SlidingWindowOptions options;
	std::string rawlog_path;
	std::string online_tum, lagged_tum;  ///< output files ("" = not written)
	std::size_t max_steps = 0;           ///< 0 = all
	std::size_t print_every = 100;       ///< 0 = no progress lines

   private:
	static void print_step(const swba::estimators::MrptSlidingWindow& slam, const swba::estimators::StepSummary& s);
	static void print_landmarks(swba::estimators::MrptSlidingWindow& slam);
};
