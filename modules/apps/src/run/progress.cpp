#include "progress.h"

#include <unistd.h>

#include <cstdio>
#include <iostream>

namespace swba::apps
{
ProgressLine::ProgressLine(std::ostream& log, bool enabled, std::string label, std::size_t total)
	: log_(log), enabled_(enabled), label_(std::move(label)), total_(total), start_(SteadyClock::now()), last_(start_)
{
	tty_ = (&log == &std::cerr) && ::isatty(2);
}

void ProgressLine::update(std::size_t done)
{
	if (!enabled_) return;
	const auto now = SteadyClock::now();
	const double since_start = std::chrono::duration<double>(now - start_).count();
	const double since_last = std::chrono::duration<double>(now - last_).count();
	if (since_start < 1.0 || (printed_ && since_last < (tty_ ? 0.25 : 10.0))) return;
	last_ = now;
	printed_ = true;
	char buf[64];
	std::snprintf(buf, sizeof(buf), " (%.1f s)", since_start);
	const std::string text = label_ + ": step " + std::to_string(done) + "/" + std::to_string(total_) + buf;
	if (tty_)
		log_ << "\r" << text << "\x1b[K" << std::flush;
	else
		log_ << text << "\n" << std::flush;
}

void ProgressLine::announce(const std::string& what)
{
	if (!enabled_) return;
	log_ << label_ << ": " << what << (tty_ ? "" : "\n") << std::flush;
	printed_ = true;
}

void ProgressLine::finish()
{
	if (!enabled_ || finished_) return;
	finished_ = true;
	if (!printed_) return;
	char buf[64];
	std::snprintf(buf, sizeof(buf), "%.1f s", seconds_since(start_));
	if (tty_)
		log_ << "\r" << label_ << ": done in " << buf << "\x1b[K\n" << std::flush;
	else
		log_ << label_ << ": done in " << buf << "\n" << std::flush;
}
}  // namespace swba::apps
