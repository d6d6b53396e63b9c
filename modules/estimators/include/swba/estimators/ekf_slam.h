/** \file ekf_slam.h
 * MRPT's EKF range-bearing SLAM run in-process over the steps of a rawlog, as the peer of the window
 * estimator: mrpt::slam::CRangeBearingKFSLAM (6D robot, 3D landmarks) or, for a planar rawlog,
 * mrpt::slam::CRangeBearingKFSLAM2D (2D robot, 2D landmarks, range-yaw readings), as MRPT's kf-slam
 * application runs it with kf_implementation = CRangeBearingKFSLAM2D. An MRPT exception
 * (the EKF throws on kf-slam_6D_demo_noncentered) is recorded, never propagated. */
#pragma once

#include <swba/estimators/pose_model.h>
#include <swba/io/rawlog.h>

#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/CPose3DQuat.h>

#include <map>

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace swba::estimators
{
/** Options of run_ekf_slam(). Precedence for each value: this struct > the INI file > default. */
struct EkfSlamOptions
{
	/** Kalman-filter method by MRPT's name: "kfEKFNaive", "kfEKFAlaDavison", "kfIKFFull" (MRPT's "kfIKF" is
	 * refused: MRPT 2.5 does not implement it).
	 * Unset: the INI's `method` if an INI is given, else "kfEKFAlaDavison" (the kf-slam INIs' choice). */
	std::optional<std::string> method;
	/** Optional kf-slam INI (e.g. /usr/share/mrpt/config_files/kf-slam/EKF-SLAM_6D_test.ini); its
	 * sections [RangeBearingKFSLAM] and [RangeBearingKFSLAM_KalmanFilter] are loaded. Default: none. */
	std::string ini_file;
	/** Sensor noise given to the EKF: range in metres, yaw and pitch in radians. Unset: the INI's
	 * std_sensor_* if an INI is given, else the observation's own sensor_std_* (first step that has
	 * a bearing-range observation; a zero std there, as 2D sensors give for pitch, keeps MRPT's
	 * default and is noted in EkfSlamResult::notes). */
	std::optional<double> std_range, std_yaw, std_pitch;
	/** Additional std of z in the motion model, metres (MRPT's std_odo_z_additional). Unset: the INI's,
	 * else MRPT's default 0. */
	std::optional<double> std_odo_z_additional_m;
	/** MRPT's data association for readings without a landmark ID: "nn" (assocNN) or "jcbb"
	 * (assocJCBB), Mahalanobis metric. Unset: the INI's if given, else MRPT's default (nn). */
	std::optional<std::string> data_association;
	/** Which filter: Spatial = CRangeBearingKFSLAM, Planar = CRangeBearingKFSLAM2D (which has no pitch
	 * noise and no z motion noise: std_pitch and std_odo_z_additional_m are then not used, and noted).
	 * Default Auto: Planar when io::is_planar(steps). */
	PoseModel model = PoseModel::Auto;
	/** Process at most this many steps (0 = all). Default 0. */
	std::size_t max_steps = 0;
	/** Called after every step with (steps done, total steps); may be empty. Default empty. */
	std::function<void(std::size_t, std::size_t)> progress;
	/** Keep MRPT's console output (its log messages and CTimeLogger table). Default false: silent. */
	bool mrpt_verbose = false;
};

/** What run_ekf_slam() produced. */
struct EkfSlamResult
{
	std::string method;	 ///< the method used (MRPT's name)
	PoseModel model = PoseModel::Spatial;  ///< the filter run (Spatial: 6D, Planar: 2D)
	double std_range = 0, std_yaw = 0, std_pitch = 0;	 ///< the sensor noise used (m, rad, rad; pitch 0 in 2D)
	/** times[i] = k + 1 and poses[i] = robot pose mean after step k, for every processed step. */
	std::vector<double> times;
	std::vector<mrpt::poses::CPose3D> poses;
	/** covariances[i]: the robot pose covariance after step k (MRPT's, 7×7 over (x, y, z, qr, qx, qy, qz)
	 * or 3×3 over (x, y, φ) in 2D) in the window's tangent convention (PoseCovariance) through
	 * quaternion_to_tangent_jacobian / the SE(2) one. */
	std::vector<PoseCovariance> covariances;
	/** assigned_ids[i][j]: the landmark reading j of step i went to, for every processed step: its own ID
	 * when it has one (the filter takes it), else what MRPT's data association gave it — the landmark's
	 * index in the filter's map (matched, or inserted from this reading) — or −1 (neither). */
	std::vector<std::vector<std::int32_t>> assigned_ids;
	/** The map at the end: each landmark's mean and covariance (the filter's 3×3 / 2×2 block), by ID. */
	std::map<std::int32_t, LandmarkEstimate> landmarks_final;
	std::size_t steps_total = 0;  ///< steps given (after max_steps)
	std::size_t steps_processed = 0;  ///< steps that completed
	double seconds = 0;	 ///< wall time inside processActionObservation (all processed steps)
	double ms_per_step = 0;	 ///< seconds·1000 / steps_processed (0 if none)
	/** Process CPU time inside processActionObservation: on a loaded, shared machine a steadier
	 * measure of the EKF's cost than wall time. */
	double cpu_seconds = 0;
	double cpu_ms_per_step = 0;	 ///< cpu_seconds·1000 / steps_processed (0 if none)
	std::size_t landmarks = 0;	///< landmarks in the filter's map at the end
	/** True when MRPT threw: `failed_step` is the step k whose processing threw (its pose is not
	 * kept), `failure` a one-line message. */
	bool failed = false;
	std::size_t failed_step = 0;
	std::string failure;
	std::string failure_details;  ///< the full exception text (MRPT's include a call trace)
	/** How the options were resolved when something was not as asked (e.g. a zero observation std). */
	std::string notes;
	/** MRPT warnings logged by the filter (e.g. "LMs were not correctly predicted"), counted. */
	std::size_t mrpt_warnings = 0;
	std::string first_mrpt_warning;
};

/** ∂δ/∂(t, q) at `mean`: the Jacobian from MRPT's quaternion pose parameters (x, y, z, qr, qx, qy, qz)
 * to the right perturbation δ = [ρ, ω] of T = T̂·Exp(δ): ρ = R̂ᵀ(t − t̂) and ω = Log(R̂ᵀR(q)) ≈
 * 2·vec(q̂* ⊗ q), so ∂ρ/∂t = R̂ᵀ and ∂ω/∂q = 2 [−v̂ | ŵ I − [v̂]×] with q̂ = (ŵ, v̂). Its rows are
 * orthogonal to the quaternion's norm direction (∂ω/∂q · q̂ = 0): a covariance along it is ignored. */
Eigen::Matrix<double, 6, 7> quaternion_to_tangent_jacobian(const mrpt::poses::CPose3DQuat& mean);

/** Parses a method name ("kfEKFNaive", …, or the number 0..3); throws std::invalid_argument listing
 * the valid names otherwise. */
int ekf_method_from_name(const std::string& name);

/** Runs MRPT's CRangeBearingKFSLAM (or CRangeBearingKFSLAM2D, see EkfSlamOptions::model) over `steps` (from swba::io::read_rawlog). Throws
 * std::invalid_argument / std::runtime_error only for bad options (unknown method, missing INI,
 * non-positive noise, empty steps); an exception of MRPT during a step is recorded in the result. */
EkfSlamResult run_ekf_slam(const std::vector<io::RawlogStep>& steps, const EkfSlamOptions& options = {});
}  // namespace swba::estimators
