/** \file run_options.h
 * Options of `swba run` (swba::apps::RunOptions) and their INI file, in MRPT's
 * CLoadableOptions style (sections [run], [window], [solver], [ekf], [sensor], [odometry], and for
 * inertial rawlogs [sensors], [inertial], [imu]; read with
 * mrpt::config::CConfigFile). Each options struct declares its own keys next to itself
 * (SlidingWindowOptions, SolverOptions, SensorNoiseOptions, OdometryInformationOptions::ini_keys); this
 * file adds the run's own ([run], the window sweep, [ekf]) and composes them. Unlike MRPT, an unknown or misspelt section or key is an error
 * that lists the known ones, and a value that does not parse completely is an error naming the key.
 * share/config/swba_run.ini documents every key with its unit and default.
 *
 * Precedence: built-in defaults < INI file (load_run_config) < command line (the app sets only the
 * options given on it). */
#pragma once

#include <swba/core/ini.h>
#include <swba/estimators/sliding_window.h>
#include <swba/estimators/inertial_window.h>
#include <swba/io/observation_rawlog.h>

#include <cstddef>
#include <string>
#include <vector>

namespace swba::apps
{
/** Everything `swba run` does. Defaults are those of share/config/swba_run.ini. */
struct RunOptions
{
	/** Rawlog to run on. "" = the default dataset (the app fills in kf-slam_6D_demo.rawlog). */
	std::string rawlog;
	/** MRPT ground-truth robot path (`x y z yaw pitch roll` per row). "" = `<rawlog name>_ground_truth_robot_path.txt`
	 * next to the rawlog if it exists, else no APE. */
	std::string ground_truth;
	/** A rawlog holding the same readings in the same order with their landmark IDs: the truth the
	 * association of a rawlog without IDs is measured against (the share of readings given their true
	 * landmark). "" = the simulator's landmark file next to the rawlog, if any. */
	std::string association_truth;
	/** Output directory (created). Default "swba_out". */
	std::string out_dir = "swba_out";
	/** Window sizes W (each ≥ 2). Default {5, 10, 20, 30}. */
	std::vector<int> windows = {5, 10, 20, 30};
	/** Landmark policies to run (each gives its own rows). Default {Slam}. */
	std::vector<estimators::LandmarkPolicy> policies = {estimators::LandmarkPolicy::Slam};
	/** First-estimate Jacobians on/off (each value gives its own rows). Default {true}. */
	std::vector<bool> fej = {true};
	/** Run MRPT's EKF (each method in ekf_methods). Default true. */
	bool run_ekf = true;
	/** MRPT Kalman-filter methods (kfEKFNaive, kfEKFAlaDavison, kfIKFFull). Default {kfEKFAlaDavison, kfEKFNaive}. */
	std::vector<std::string> ekf_methods = {"kfEKFAlaDavison", "kfEKFNaive"};
	/** Optional kf-slam INI for the EKF's other options (its std_sensor_* are overridden by `window.sensor_std_*`
	 * when those are set). Default "" (MRPT's defaults). */
	std::string ekf_ini;
	/** Run the batch estimator (window = ∞). Default true. */
	bool run_batch = true;
	/** LM iteration limit of the batch solve. Default 100. */
	int batch_max_iterations = 100;
	/** Also run the full-history causal optimum ("online, W = ∞"; O(steps²)). Default false. */
	bool run_causal = false;
	/** Process at most this many steps (0 = all). Default 0. */
	std::size_t max_steps = 0;
	/** Write gnuplot plots when gnuplot is found. Default true. */
	bool plots = true;
	/** Progress lines on stderr for estimators running longer than a second. Default true. */
	bool progress = true;
	/** Each solve's summary on stderr: one line per window step, the batch's full solver report.
	 * Default false. */
	bool verbose = false;
	/** The window/batch options: solver (threads included), sensor noise (also given to the EKF),
	 * odometry floors, gauge, landmarks. window_size, policy and first_estimate_jacobians are taken
	 * from the lists above for each row. */
	estimators::SlidingWindowOptions window;
	/** Inertial rawlogs (observation format): which sensor label plays which role ([sensors]). */
	io::SensorRoles sensors;
	/** Inertial rawlogs: the window's keyframes, gauge and re-integration ([inertial]) and the IMU's noise
	 * densities, random walks and gravity ([imu], in measurements.noise). window_size is taken from the
	 * window sizes above for each row. */
	estimators::InertialWindowOptions inertial;

	/** Throws std::invalid_argument with a one-line reason naming the option. */
	void validate() const;
};

/** All keys, in file order. */
const IniKeys<RunOptions>& run_config_key_table();
/** The options as an INI file (every key, current values) — written to DIR/config.ini. */
std::string format_run_config(const RunOptions& options);

/** Every INI key as "section.key" with its unit, meaning and default, in file order (what the
 * error message for an unknown key lists, and what share/config/swba_run.ini documents). */
const std::vector<std::string>& run_config_keys();

/** Loads the INI file `path` over `options` (keys not in the file keep their value). Throws
 * std::runtime_error "config '<path>': …" on a missing file, an unknown section or key (listing the
 * known keys of that section, or the known sections), or a value that does not parse (naming
 * [section] key and the value). */
void load_run_config(const std::string& path, RunOptions& options);
/** As load_run_config(path, …) from INI text; `source_name` is used in messages. */
void load_run_config_text(const std::string& text, const std::string& source_name, RunOptions& options);

/** The largest window size a list may hold: a window of a million poses is a batch solve with a
 * million-pose prior, far beyond what a run can hold in memory. */
inline constexpr int kMaxWindowSize = 1000000;

/** "5,10,20" → {5, 10, 20}. Throws std::invalid_argument ("<what>: …"; no prefix when `what` is empty) on
 * an empty list, a non-integer or a window outside [2, kMaxWindowSize]. */
std::vector<int> parse_window_list(const std::string& text, const std::string& what = "windows");
/** "slam" | "constant-time" | "map", a comma-separated list of them (duplicates dropped), "both"
 * (slam, constant-time) or "all". */
std::vector<estimators::LandmarkPolicy> parse_policy_list(const std::string& text);
/** "on" | "off" | "both" (also true/false/1/0). */
std::vector<bool> parse_fej_list(const std::string& text);
/** "kfEKFNaive,kfEKFAlaDavison" (each checked with estimators::ekf_method_from_name; numbers mapped to names). */
std::vector<std::string> parse_ekf_method_list(const std::string& text);
/** Comma-separated items, trimmed; empty items are an error. */
std::vector<std::string> split_list(const std::string& text, const std::string& what);
}  // namespace swba::apps
