/** \file simulate.h
 * `swba simulate`: one simulated rawlog from a simul-landmarks INI (MRPT's mrpt-apps) with a given
 * random seed, so that a sweep job can make its own rawlog (doc/sweeps.md). The INI's [Params]
 * random_seed, outFile and outDir are replaced; everything else (path, landmarks, noise) is the INI's.
 * simul-landmarks writes into its working directory and reports errors on stdout with exit code 0, so
 * its outputs are checked, not its exit code. */
#pragma once

#include <cstddef>
#include <iosfwd>
#include <string>

namespace swba::apps
{
struct SimulateOptions
{
	/** simul-landmarks INI (e.g. share/rawlogs/kf-slam_6D_noisy.ini); must have [Params] random_seed. */
	std::string ini;
	/** Seed of simul-landmarks' random generator (> 0: deterministic). (Default = 1) */
	long seed = 1;
	/** Output directory, created. (Default = ".") */
	std::string out_dir = ".";
	/** Base name of the outputs; "" = <INI stem>_seed<seed>. (Default = "") */
	std::string name;
	/** The simul-landmarks executable: a name looked up on PATH, or a path. (Default = "simul-landmarks") */
	std::string program = "simul-landmarks";
	/** Keep simul-landmarks' rawlog as written, without declare_unperturbed_odometry_exact. (Default = false) */
	bool keep_declared_noise = false;

	/** Throws std::invalid_argument naming the option. */
	void validate() const;
	/** `name`, or <INI stem>_seed<seed> when it is empty. */
	std::string output_name() const;
};

/** What simulate_rawlog wrote: mrpt-common's naming, so `swba run RAWLOG` finds the ground truth. */
struct SimulatedRawlog
{
	std::string rawlog;        ///< <out_dir>/<name>.rawlog
	std::string ground_truth;  ///< <out_dir>/<name>_ground_truth_robot_path.txt (x y z yaw pitch roll per row)
	std::string landmarks;     ///< <out_dir>/<name>_ground_truth.txt
	std::string ini;           ///< <out_dir>/<name>.ini: the INI simul-landmarks ran with
	std::string log;           ///< <out_dir>/<name>.simul-landmarks.log: its output
	/** Odometry increments re-declared exact by declare_unperturbed_odometry_exact. */
	std::size_t exact_increments = 0;
};

/** simul-landmarks holds the robot still for its first steps and writes their zero odometry increment
 * without noise, but declares the covariance of a moving step for it (σ = odometryNoiseXY_std, ...):
 * the rawlog states noise its data does not have, which makes every estimator's covariance too large
 * for the rest of the run (the motionless start is where the map is anchored), and NEES too low. This
 * rewrites `rawlog` with a zero covariance for every odometry increment that is exactly zero (a 3D
 * movement's mean, or a 2D movement's raw odometry reading; a perturbed increment is never exactly zero)
 * and leaves everything else as it was. Returns how many were re-declared. Throws std::runtime_error
 * naming the file when it cannot be read or written. */
std::size_t declare_unperturbed_odometry_exact(const std::string& rawlog);

/** The INI text of `ini_text` with [Params] random_seed = seed, outFile = <name>.rawlog, outDir = ".",
 * show_in_3d = false. Throws std::runtime_error naming `source` when [Params] has no random_seed. */
std::string simulation_ini(const std::string& ini_text, const std::string& source, long seed, const std::string& name);

/** Runs simul-landmarks and moves its outputs into options.out_dir. Throws std::runtime_error naming
 * the INI, the program or the log file when it fails. A line on `log` says what was written. */
SimulatedRawlog simulate_rawlog(const SimulateOptions& options, std::ostream& log);
}  // namespace swba::apps
