/** \file sensor_noise.h
 * The range-bearing sensor noise every estimator of a run uses (window, batch, MRPT's EKF), in one
 * unit convention: metres and radians. Degrees appear only in the INI keys and on the command line. */
#pragma once

#include <swba/core/ini.h>
#include <swba/io/rawlog.h>

#include <Eigen/Core>

#include <string>

namespace swba::estimators
{
struct SensorNoiseOptions
{
	/** Standard deviations of range (m), yaw and pitch (rad). A value ≤ 0 means "the observation's
	 * own sensor_std_*". Default 0 (all from the observation). */
	double std_range = 0.0, std_yaw = 0.0, std_pitch = 0.0;

	/** Each set value, else the reading's own (io::RangeBearingReading::has_own_noise), else the
	 * step's: (range, yaw, pitch) in m, rad, rad. Without a reading: the set values, else the step's.
	 * Throws std::invalid_argument naming the step when one of them is not > 0 (e.g. a 2D sensor's pitch). */
	Eigen::Vector3d resolve(const io::RawlogStep& step, const io::RangeBearingReading* reading = nullptr) const;
	/** (range, yaw) as resolve() does, for a 2D sensor (its pitch std, usually 0, is not used). */
	Eigen::Vector2d resolve_range_yaw(const io::RawlogStep& step, const io::RangeBearingReading* reading = nullptr) const;
	/** Throws std::invalid_argument when a value is not finite. */
	void validate() const;
	/** The INI keys in `section`: std_range_m, std_yaw_deg, std_pitch_deg (≥ 0; 0 = the observation's own). */
	static IniKeys<SensorNoiseOptions> ini_keys(const std::string& section);
};
}  // namespace swba::estimators
