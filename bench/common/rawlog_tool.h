// What the benchmarks' rawlog tools (swba_make_outlier_rawlog, swba_range_noise) share: a visit of every
// bearing-range observation of an MRPT rawlog, and a main that reports an error in one line.
#pragma once

#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/obs/CSensoryFrame.h>

#include <exception>
#include <iostream>
#include <string>

namespace swba::bench
{
/** Calls f(CObservationBearingRange&) for each bearing-range observation of `rawlog`, in file order,
 * inside sensory frames and bare (observation-format rawlogs). */
template <class F>
void for_each_bearing_range(mrpt::obs::CRawlog& rawlog, F f)
{
	const auto visit = [&f](const mrpt::obs::CObservation::Ptr& o) {
		if (auto br = std::dynamic_pointer_cast<mrpt::obs::CObservationBearingRange>(o)) f(*br);
	};
	for (std::size_t i = 0; i < rawlog.size(); i++)
	{
		if (rawlog.getType(i) == mrpt::obs::CRawlog::etSensoryFrame)
			for (const auto& o : *rawlog.getAsObservations(i)) visit(o);
		else if (rawlog.getType(i) == mrpt::obs::CRawlog::etObservation)
			visit(rawlog.getAsObservation(i));
	}
}

/** run(argc, argv)'s exit code; an exception is printed as "<name>: <what>" and gives 1. */
template <class Run>
int tool_main(const char* name, int argc, char** argv, Run run)
{
	try
	{
		return run(argc, argv);
	}
	catch (const std::exception& e)
	{
		std::cerr << name << ": " << e.what() << "\n";
		return 1;
	}
}
}  // namespace swba::bench
