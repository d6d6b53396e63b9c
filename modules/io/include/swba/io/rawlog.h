/** \file rawlog.h
 * MRPT rawlogs with odometry + range-bearing landmark observations (the kf-slam demos and what
 * `simul-landmarks` writes), read into a vector of steps; and the odometry covariance converted
 * into the information matrix of an SE(3) between-factor in MRPT's pseudo-log tangent space.
 *
 * Step pairing (as CRawlog::readActionObservationPair and MRPT's kf-slam app): objects before the
 * first CActionCollection are skipped; step k = (the k-th CActionCollection, the next CSensoryFrame).
 * On the kf-slam demos (stored SF0, AC0, SF1, AC1, …) step k = (AC_k, SF_{k+1}): 599 steps from 600
 * poses. The estimate after step k has time t = k + 1 and pairs with ground-truth row k + 1. */
#pragma once

#include <swba/core/ini.h>

#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace swba::io
{
/** One landmark reading of a CObservationBearingRange, in the sensor frame:
 * l = sensor⁻¹ ⊕ landmark, range = |l|, yaw = atan2(l.y, l.x), pitch = −asin(l.z / range). */
struct RangeBearingReading
{
	int32_t landmark_id = -1;  ///< MRPT's landmarkID (−1: unknown, needs data association)
	double range = 0.0;	 ///< metres
	double yaw = 0.0;  ///< radians
	double pitch = 0.0;	 ///< radians
	/** The reading's own noise σ (m, rad, rad) when its observation declares per-reading covariances
	 * (CObservationBearingRange::validCovariances: the square roots of the covariance's diagonal; the
	 * observation's sensor_std_* do not hold for it); 0 = none declared (they do). */
	double std_range = 0.0, std_yaw = 0.0, std_pitch = 0.0;
	bool has_own_noise() const { return std_range > 0; }
};

/** One estimator step: the odometry from the previous pose and the observations at the new pose. */
struct RawlogStep
{
	std::size_t index = 0;	///< k (0-based)
	std::size_t action_entry = 0;  ///< rawlog entry (object index, 0-based) of the action collection
	std::size_t frame_entry = 0;  ///< rawlog entry of the sensory frame
	/** Trajectory time of the estimate after this step (the step index is the clock). */
	double time() const { return static_cast<double>(index + 1); }

	/** False when the action collection holds no robot movement (then `odometry` is the identity
	 * with a zero covariance). */
	bool has_odometry = false;
	/** True when the odometry came from a CActionRobotMovement2D (lifted to 3D: z, pitch and roll
	 * are 0 with zero variance). */
	bool odometry_is_2d = false;
	/** Pose increment, mean and 6×6 covariance in MRPT's (x, y, z, yaw, pitch, roll) order. */
	mrpt::poses::CPose3DPDFGaussian odometry;

	/** False when the sensory frame holds no CObservationBearingRange (then `readings` is empty
	 * and the sensor fields below are copied from the previous step, or defaults). */
	bool has_observation = false;
	/** Valid readings (bad ones are dropped and counted in `skipped_readings`). */
	std::vector<RangeBearingReading> readings;
	std::size_t skipped_readings = 0;
	/** CObservationBearingRange::sensorLocationOnRobot. */
	mrpt::poses::CPose3D sensor_pose;
	/** The observation's own noise (sensor_std_range in metres, _yaw/_pitch in radians). */
	double sensor_std_range = 0.0, sensor_std_yaw = 0.0, sensor_std_pitch = 0.0;

	/** The objects as read (for MRPT's EKF). When readings were dropped as invalid, `observations`
	 * is a copy whose bearing-range observations hold only the valid readings, so that every
	 * consumer sees the same data. */
	mrpt::obs::CActionCollection::Ptr actions;
	mrpt::obs::CSensoryFrame::Ptr observations;
};

/** Options of read_rawlog(). */
struct RawlogReaderOptions
{
	/** Readings with landmarkID < 0 are invalid (skipped with a counted warning). Default: true
	 * (no data association here). */
	bool require_landmark_ids = true;
	/** A truncated or corrupt rawlog is an error (default). When true, the complete steps read
	 * before the damage are kept and `Rawlog::truncated` is set with a warning. */
	bool allow_truncated = false;
	/** Read at most this many steps (0 = all). Default 0. */
	std::size_t max_steps = 0;
	/** At most this many warning texts are kept in `Rawlog::warnings` (all are counted). Default 20. */
	std::size_t max_warning_texts = 20;
	/** Memory the reading may take, in bytes, beyond what the process holds when it starts; an
	 * object whose declared length or count would exceed it ends the reading as a corrupt entry
	 * (swba::ScopedMemoryBudget: the process's address space is capped while the file is read, so
	 * the cap is process-wide; not in AddressSanitizer builds). 0 = no cap. Default kAutoMemoryBudget:
	 * auto_memory_budget() of the file. */
	std::uint64_t memory_budget = kAutoMemoryBudget;
	/** Decode the file once in a child process before reading it (default true): an object on which
	 * MRPT's decoder crashes (it dereferences null objects stored in the file) or exhausts its memory
	 * budget (also under AddressSanitizer, where the address-space cap is unavailable) then ends the
	 * reading as a corrupt entry instead of killing the process. Costs a second decoding of the file. */
	bool probe_decoder = true;

	static constexpr std::uint64_t kAutoMemoryBudget = ~std::uint64_t(0);
};

/** The default memory budget of reading a rawlog whose serialised data (decompressed, for gzip) has
 * `data_bytes` bytes: 256 MiB + 16 × data_bytes. No object can legitimately need more memory than
 * a small multiple of the bytes that encode it, so this lets every real file through (its content
 * is as large as it declares) and stops the length fields of a corrupt file from asking for
 * gigabytes that are not in it. */
std::uint64_t auto_memory_budget(std::uint64_t data_bytes);

/** Turns MRPT (action collection, sensory frame) pairs into RawlogSteps numbered 0, 1, 2, … with
 * read_rawlog()'s rules: the first robot movement (2D or 3D) is the odometry (none → has_odometry =
 * false); the frame's CObservationBearingRange readings become `readings`, invalid single readings
 * (non-finite, range ≤ 0, landmarkID < 0 when IDs are required) are dropped and counted, and
 * `observations` is then a cleaned copy of the frame; the sensor description is carried to steps
 * whose frame has none. read_rawlog() and swba::estimators::MrptStepConverter both use it. */
class RawlogStepConverter
{
   public:
	explicit RawlogStepConverter(bool require_landmark_ids = true) : require_landmark_ids_(require_landmark_ids) {}

	/** The next step. `where` names it in messages ("step 12 (rawlog entries 25/26)"); `warn`, if
	 * set, receives one text per dropped reading. Throws std::invalid_argument("<where>: <what>")
	 * on a null pointer, a non-finite odometry mean or covariance, a negative odometry variance, a
	 * non-finite sensor pose or noise, or bearing-range observations with different sensor
	 * poses/noise in one frame; the step counter then does not advance. */
	RawlogStep convert(const mrpt::obs::CActionCollection::Ptr& actions, const mrpt::obs::CSensoryFrame::Ptr& frame,
					   const std::string& where, const std::function<void(const std::string&)>& warn = {});

	/** Steps converted so far (the index the next step gets). */
	std::size_t steps() const { return steps_; }
	/** CObservationBearingRange objects seen so far. */
	std::size_t bearing_range_observations() const { return bearing_range_observations_; }

   private:
	bool require_landmark_ids_;
	std::size_t steps_ = 0;
	std::size_t bearing_range_observations_ = 0;
	mrpt::poses::CPose3D last_sensor_pose_;  ///< carried to steps without a bearing-range observation
	double last_std_[3] = {0, 0, 0};
};

/** A rawlog read into steps, with counts for reports. */
struct Rawlog
{
	std::string path;
	std::vector<RawlogStep> steps;
	std::size_t entries = 0;  ///< objects read from the file
	std::size_t ignored_entries = 0;  ///< objects not used (leading SF0, trailing action, other types)
	std::size_t steps_with_odometry = 0;
	std::size_t steps_with_2d_odometry = 0;
	std::size_t steps_without_observation = 0;
	std::size_t readings = 0;  ///< valid readings kept
	std::size_t skipped_readings = 0;  ///< invalid readings dropped (NaN / ≤ 0 range, bad angles, id < 0)
	std::size_t readings_with_own_noise = 0;  ///< valid readings with their own covariance (validCovariances)
	std::size_t distinct_landmarks = 0;	 ///< distinct landmark IDs (≥ 0) among the valid readings
	bool truncated = false;	 ///< only with RawlogReaderOptions::allow_truncated
	std::size_t warning_count = 0;
	std::vector<std::string> warnings;	///< the first max_warning_texts warnings, one line each
};

/** Reads a whole rawlog (gzip-compressed or plain). Throws std::runtime_error naming the file and
 * the entry/step when: the file is missing or unreadable; it is not a rawlog; it is truncated or
 * corrupt (unless allow_truncated; gzip truncation is also detected when it ends on an object
 * boundary, by inflating the gzip members once before the reading); it yields no step; no step has odometry; no step has
 * a valid range-bearing reading; an odometry mean or covariance is not finite, or a covariance has
 * a negative variance; a sensory frame holds several bearing-range observations with different
 * sensor poses; a per-reading covariance (validCovariances) correlates range, yaw and pitch (only
 * their variances are taken). Single invalid readings are dropped and counted (see RawlogStep::skipped_readings).
 * Corrupt length fields: MRPT 2.5's deserialisation allocates whatever a length or count field asks
 * for (gigabytes from a few hundred bytes; reproducers in fuzz/findings/mrpt/) before any check here
 * can run; options.memory_budget bounds that (such a file is then reported as corrupt at the entry
 * whose object asked for it). For gzip files the data size is that scan's decompressed size.
 * Concatenated gzip members read as one stream; bytes after the last member are ignored with a
 * warning (zlib's gzread ignores them too). */
Rawlog read_rawlog(const std::string& path, const RawlogReaderOptions& options = {});

/** One line from an exception text: for MRPT's ("==== MRPT exception ====", "Message: …",
 * "Location: …", call stack) the message and "File.cpp:line"; otherwise the first non-empty line.
 * Control characters and bytes that may be raw file contents are written as \xNN; with `keep_utf8`
 * (the terminal's locale is UTF-8) well-formed UTF-8 characters such as "≥" are kept as they are. */
std::string mrpt_exception_summary(const std::string& what, bool keep_utf8 = false);

/** Whether the environment's locale for characters (LC_ALL, else LC_CTYPE, else LANG) is UTF-8. */
bool locale_is_utf8();

/* MRPT ground-truth robot paths are read by swba::eval::read_mrpt_ground_truth (swba/eval/trajectory.h). */

/** J = ∂ Log(Z⁻¹ · Z(ypr + d)) / ∂d at d = 0, for Z = `mean`, d a perturbation of MRPT's
 * (x, y, z, yaw, pitch, roll) parameters and Log MRPT's pseudo-log [ρ, ω] (Lie::SE<3>::log).
 * Analytic: ∂ρ/∂(x,y,z) = Rᵀ, ∂ω/∂(yaw,pitch,roll) = body angular rates of the ZYX Euler angles
 * [(−sin p, cos p sin r, cos p cos r), (0, cos r, −sin r), (1, 0, 0)] (columns), other blocks 0. */
Eigen::Matrix<double, 6, 6> ypr_to_tangent_jacobian(const mrpt::poses::CPose3D& mean);

/** Options of odometry_information(). */
struct OdometryInformationOptions
{
	/** Floor on the standard deviation of every translational tangent direction, metres. Default 1e-4. */
	double min_sigma_translation = 1e-4;
	/** Floor on the standard deviation of every rotational tangent direction, radians. Default 1e-4. */
	double min_sigma_rotation = 1e-4;

	/** The INI keys in `section`: min_sigma_translation_m, min_sigma_rotation_rad (both > 0). */
	static IniKeys<OdometryInformationOptions> ini_keys(const std::string& section);
};

/** Σ_tangent = J Σ_ypr Jᵀ (J from ypr_to_tangent_jacobian), without any floor. */
Eigen::Matrix<double, 6, 6> odometry_tangent_covariance(const mrpt::poses::CPose3DPDFGaussian& odometry);

/** Information matrix of the between-factor residual r = Log(Z⁻¹·Ti⁻¹·Tj) = [ρ, ω] for the odometry
 * Z = odometry.mean. The covariance Σ_tangent is floored in the σ_min-scaled space: with
 * S = diag(σ_min,t ×3, σ_min,r ×3), A = S⁻¹ Σ S⁻¹ = V Λ Vᵀ, each eigenvalue is raised to at least 1,
 * so every direction has at least the floor variance (for a diagonal Σ this is exactly
 * Σ_ii ← max(Σ_ii, σ_min²)); 2D odometry (zero z/pitch/roll variance) thus gets finite information
 * 1/σ_min² there. Returns S⁻¹ V Λ'⁻¹ Vᵀ S⁻¹, symmetric positive definite. Throws
 * std::invalid_argument on non-finite input or non-positive floors. */
Eigen::Matrix<double, 6, 6> odometry_information(
	const mrpt::poses::CPose3DPDFGaussian& odometry, const OdometryInformationOptions& options = {});

/** Information of the planar part (ρx, ρy, ωz) of the between-factor residual, for a robot on the
 * plane: the marginal of Σ_tangent over those three directions (no information is taken from the
 * z/pitch/roll rows, which a 2D odometry leaves at zero variance), floored like odometry_information
 * (translation floor on ρx, ρy, rotation floor on ωz). Throws as odometry_information. */
Eigen::Matrix3d planar_odometry_information(const mrpt::poses::CPose3DPDFGaussian& odometry,
											const OdometryInformationOptions& options = {});

/** A step of a planar (2D) robot: its odometry, if any, is a CActionRobotMovement2D and every
 * reading has pitch exactly 0 (a 2D sensor measures range and yaw only). */
bool is_planar_step(const RawlogStep& step);
/** Every step is planar and at least one has odometry: the 2D model applies (what MRPT's
 * CRangeBearingKFSLAM2D and the window's planar model estimate). */
bool is_planar(const std::vector<RawlogStep>& steps);
}  // namespace swba::io
