// A progress line on the log for `swba run`'s long tasks.
#pragma once

#include <swba/core/timing.h>

#include <cstddef>
#include <iosfwd>
#include <string>

namespace swba::apps
{
/** A progress line on `log` for a task that runs longer than a second: on a terminal one line
 * rewritten in place ("\r"), otherwise a line every 10 s; "<label>: done in t s" at the end when
 * anything was printed. Disabled (prints nothing) when `enabled` is false. */
class ProgressLine
{
   public:
	ProgressLine(std::ostream& log, bool enabled, std::string label, std::size_t total);
	~ProgressLine() { finish(); }
	ProgressLine(const ProgressLine&) = delete;
	ProgressLine& operator=(const ProgressLine&) = delete;

	/** `done` of the `total` steps are finished. */
	void update(std::size_t done);
	/** Announces a single long task (no steps): printed at once. */
	void announce(const std::string& what);
	/** Prints "done in t s" if anything was printed; later calls do nothing. */
	void finish();

   private:
	std::ostream& log_;
	bool enabled_;
	std::string label_;
	std::size_t total_;
	SteadyClock::time_point start_, last_;
	bool tty_ = false, printed_ = false, finished_ = false;
};
}  // namespace swba::apps
