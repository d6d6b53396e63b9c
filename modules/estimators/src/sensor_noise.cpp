#include <swba/estimators/sensor_noise.h>

#include <cmath>
#include <stdexcept>

namespace swba::estimators
{
namespace
{
constexpr double kDegToRad = 3.14159265358979323846 / 180.0;

/** A noise key in degrees over a field in radians; 0 stays 0 ("the observation's own"). */
IniKey<SensorNoiseOptions> degrees_key(const std::string& section, const char* key, const char* meaning,
									   double SensorNoiseOptions::*field)
{
	return {section, key, "deg", meaning,
			[field](const std::string& v, SensorNoiseOptions& o) { o.*field = ini::parse_non_negative(v) * kDegToRad; },
			[field](const SensorNoiseOptions& o) { return ini::format_double(o.*field > 0 ? o.*field / kDegToRad : 0.0); }};
}
}  // namespace

namespace
{
/** `reading` if it declares its own noise, else nullptr (the step's holds). */
const io::RangeBearingReading* own_noise(const io::RangeBearingReading* reading)
{
	return reading && reading->has_own_noise() ? reading : nullptr;
}

void check_positive(const Eigen::VectorXd& s, const io::RawlogStep& step, const io::RangeBearingReading* own)
{
	for (Eigen::Index i = 0; i < s.size(); i++)
		if (!(s[i] > 0))
			throw std::invalid_argument("step " + std::to_string(step.index) + ": sensor noise is not positive (" +
										(own ? "a reading's own covariance" : "the observation's sensor_std_*") +
										"; set it in the options: [sensor] or --sensor-std-*)");
}
}  // namespace

Eigen::Vector3d SensorNoiseOptions::resolve(const io::RawlogStep& step, const io::RangeBearingReading* reading) const
{
	const Eigen::Vector2d ry = resolve_range_yaw(step, reading);
	const io::RangeBearingReading* own = own_noise(reading);
	const Eigen::Vector3d s(ry[0], ry[1], std_pitch > 0 ? std_pitch : own ? own->std_pitch : step.sensor_std_pitch);
	check_positive(s, step, own);
	return s;
}

Eigen::Vector2d SensorNoiseOptions::resolve_range_yaw(const io::RawlogStep& step,
													  const io::RangeBearingReading* reading) const
{
	const io::RangeBearingReading* own = own_noise(reading);
	const Eigen::Vector2d s(std_range > 0 ? std_range : own ? own->std_range : step.sensor_std_range,
							std_yaw > 0 ? std_yaw : own ? own->std_yaw : step.sensor_std_yaw);
	check_positive(s, step, own);
	return s;
}

void SensorNoiseOptions::validate() const
{
	for (double s : {std_range, std_yaw, std_pitch})
		if (!std::isfinite(s)) throw std::invalid_argument("sensor noise must be finite");
}

IniKeys<SensorNoiseOptions> SensorNoiseOptions::ini_keys(const std::string& section)
{
	using S = std::string;
	using O = SensorNoiseOptions;
	return {
		{section, "std_range_m", "m", "range noise for every estimator; 0 = the observation's own sensor_std_range",
		 [](const S& v, O& o) { o.std_range = ini::parse_non_negative(v); },
		 [](const O& o) { return ini::format_double(o.std_range > 0 ? o.std_range : 0.0); }},
		degrees_key(section, "std_yaw_deg", "yaw noise for every estimator; 0 = the observation's own sensor_std_yaw",
					&O::std_yaw),
		degrees_key(section, "std_pitch_deg",
					"pitch noise for every estimator; 0 = the observation's own sensor_std_pitch", &O::std_pitch),
	};
}
}  // namespace swba::estimators
