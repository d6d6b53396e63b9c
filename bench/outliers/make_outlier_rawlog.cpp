// swba_make_outlier_rawlog: copies an MRPT rawlog, replacing a fraction of its bearing-range readings by
// gross errors: the range moved by ±[range-min, range-max] m and the yaw by ±[yaw-min-deg, yaw-max-deg]
// (optionally the pitch too), signs and magnitudes uniform. Everything else is copied as read.
//
// Deterministic for a seed: every reading draws the same five numbers from one 64-bit Mersenne twister
// whatever the fraction, so the outliers of a smaller fraction are a subset of those of a larger one
// with the same seed (1 % ⊂ 5 %), and the same seed gives the same file.
#include "../common/rawlog_tool.h"

#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/obs/CSensoryFrame.h>

#include <cmath>
#include <cstdint>
#include <iostream>
#include <random>
#include <stdexcept>
#include <string>

namespace
{
struct Gross
{
	double fraction = 0.01;
	double range_min = 1.0, range_max = 3.0;  ///< m
	double yaw_min = 0.2, yaw_max = 0.6;      ///< rad
	bool pitch = false;                       ///< also move the pitch by the yaw's magnitudes
};

/** Uniform in [0, 1) from the top 53 bits (the same on every platform, unlike std's distributions). */
double uniform(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

/** Draws one reading's numbers and, when it is an outlier, moves it. Returns whether it was moved. */
bool corrupt(mrpt::obs::CObservationBearingRange::TMeasurement& m, const Gross& g, std::mt19937_64& rng)
{
	double u[5];
	for (double& x : u) x = uniform(rng);
	if (u[0] >= g.fraction) return false;
	const auto signed_in = [](double s, double t, double lo, double hi) { return (s < 0.5 ? -1.0 : 1.0) * (lo + t * (hi - lo)); };
	const double dr = signed_in(u[1], u[2], g.range_min, g.range_max);
	m.range = static_cast<float>(m.range + dr > 0 ? m.range + dr : m.range - dr);  // keep the range positive
	const double da = signed_in(u[3], u[4], g.yaw_min, g.yaw_max);
	m.yaw = std::remainder(m.yaw + da, 2 * M_PI);
	if (g.pitch) m.pitch = std::remainder(m.pitch - da, 2 * M_PI);
	return true;
}

int run(int argc, char** argv)
{
	TCLAP::CmdLine cmd("Copies a rawlog with a fraction of its bearing-range readings replaced by gross errors.", ' ');
	TCLAP::UnlabeledValueArg<std::string> in("IN", "input rawlog", true, "", "IN", cmd);
	TCLAP::UnlabeledValueArg<std::string> out("OUT", "output rawlog (gzip, as MRPT writes)", true, "", "OUT", cmd);
	TCLAP::ValueArg<double> fraction("", "fraction", "share of readings made outliers, in [0, 1]. (Default: 0.01)", false,
									 0.01, "F", cmd);
	TCLAP::ValueArg<std::uint64_t> seed("", "seed", "random seed. (Default: 1)", false, 1, "N", cmd);
	TCLAP::ValueArg<double> rmin("", "range-min", "smallest range error, m. (Default: 1)", false, 1.0, "M", cmd);
	TCLAP::ValueArg<double> rmax("", "range-max", "largest range error, m. (Default: 3)", false, 3.0, "M", cmd);
	TCLAP::ValueArg<double> ymin("", "yaw-min-deg", "smallest yaw error, deg. (Default: 11.459 = 0.2 rad)", false,
								 0.2 * 180 / M_PI, "D", cmd);
	TCLAP::ValueArg<double> ymax("", "yaw-max-deg", "largest yaw error, deg. (Default: 34.377 = 0.6 rad)", false,
								 0.6 * 180 / M_PI, "D", cmd);
	TCLAP::SwitchArg pitch("", "pitch", "also move the pitch (opposite sign, the yaw's magnitude)", cmd);
	cmd.parse(argc, argv);

	Gross g;
	g.fraction = fraction.getValue();
	g.range_min = rmin.getValue();
	g.range_max = rmax.getValue();
	g.yaw_min = ymin.getValue() * M_PI / 180;
	g.yaw_max = ymax.getValue() * M_PI / 180;
	g.pitch = pitch.getValue();
	if (!(g.fraction >= 0 && g.fraction <= 1)) throw std::invalid_argument("--fraction must be in [0, 1]");
	if (!(g.range_min >= 0 && g.range_min <= g.range_max)) throw std::invalid_argument("need 0 <= --range-min <= --range-max");
	if (!(g.yaw_min >= 0 && g.yaw_min <= g.yaw_max)) throw std::invalid_argument("need 0 <= --yaw-min-deg <= --yaw-max-deg");

	mrpt::obs::CRawlog rawlog;
	if (!rawlog.loadFromRawLogFile(in.getValue()))
		throw std::runtime_error("rawlog '" + in.getValue() + "': cannot be read");
	std::mt19937_64 rng(seed.getValue());
	std::size_t readings = 0, moved = 0;
	swba::bench::for_each_bearing_range(rawlog, [&](mrpt::obs::CObservationBearingRange& br) {
		for (auto& m : br.sensedData)
		{
			readings++;
			if (corrupt(m, g, rng)) moved++;
		}
	});
	if (!rawlog.saveToRawLogFile(out.getValue()))
		throw std::runtime_error("rawlog '" + out.getValue() + "': cannot be written");
	std::cout << "make_outlier_rawlog: " << moved << " of " << readings << " readings made outliers (fraction "
			  << g.fraction << ", seed " << seed.getValue() << ") -> " << out.getValue() << "\n";
	return 0;
}
}  // namespace

int main(int argc, char** argv) { return swba::bench::tool_main("make_outlier_rawlog", argc, argv, run); }
