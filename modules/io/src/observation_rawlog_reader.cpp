// Reading observation-format rawlogs (swba/io/observation_rawlog.h): objects are collected per role
// with their MRPT timestamps, then converted to the IMU frame with times from the earliest observation.
#include "guarded_decoder.h"

#include <swba/core/file.h>
#include <swba/io/observation_rawlog.h>
#include <swba/io/rawlog.h>

#include <mrpt/serialization/CArchive.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>

namespace swba::io
{
namespace
{
using mrpt::obs::CObservationIMU;
using mrpt::obs::CObservationRobotPose;
using mrpt::poses::CPose3D;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

struct RawPose
{
	mrpt::Clock::time_point ts;
	std::string label;
	CPose3D pose, sensor_pose;
	Matrix6d cov_ypr;
	std::size_t entry = 0;
};

struct RawImu
{
	mrpt::Clock::time_point ts;
	Eigen::Vector3d acc, gyro;
};

class ObservationReader
{
   public:
	ObservationReader(const std::string& path, const SensorRoles& roles) : roles_(roles) { out_.path = path; }
	ObservationRawlog run();

   private:
	[[noreturn]] void fail(const std::string& msg) const { throw std::runtime_error("rawlog '" + out_.path + "': " + msg); }
	std::string at_entry() const { return "entry " + std::to_string(entry_) + ": "; }
	void take(const mrpt::serialization::CSerializable::Ptr& obj);
	void take_imu(const CObservationIMU& o);
	void take_pose(const CObservationRobotPose& o);
	void check_role_labels(const std::vector<std::string>& role, const std::string& key,
						   const std::string& class_name) const;
	void read_objects();
	void check_gzip_end(const detail::GuardedDecoder& decoder);
	void convert();
	PoseReading to_imu_frame(const RawPose& p, const CPose3D& covariance_at) const;

	SensorRoles roles_;
	ObservationRawlog out_;
	std::size_t entry_ = 0;
	std::optional<std::string> imu_label_;
	std::optional<CPose3D> imu_sensor_pose_;
	std::vector<RawImu> imu_;
	std::vector<RawPose> priors_, odometry_;
	std::map<std::string, mrpt::Clock::time_point> last_ts_;
	std::optional<mrpt::Clock::time_point> origin_;
	std::map<std::string, std::set<std::string>> labels_;  ///< the sensor labels read, per observation class
};

/** Throws naming the first label of a role that no observation of `class_name` read carries, with the
 * labels the rawlog holds. */
void ObservationReader::check_role_labels(const std::vector<std::string>& role, const std::string& key,
										  const std::string& class_name) const
{
	const auto it = labels_.find(class_name);
	for (const auto& label : role)
	{
		if (it != labels_.end() && it->second.count(label)) continue;
		std::string held;
		for (const auto& [cls, names] : labels_)
		{
			held += held.empty() ? "" : "; ";
			held += cls;
			for (const auto& n : names) held += (&n == &*names.begin() ? " '" : ", '") + n + "'";
		}
		fail("[sensors] " + key + " = " + label + ": no " + class_name + " has that label (the rawlog holds " +
			 (held.empty() ? "no observation" : held) + ")");
	}
}

void ObservationReader::take_imu(const CObservationIMU& o)
{
	if (!roles_.imu.empty() && std::find(roles_.imu.begin(), roles_.imu.end(), o.sensorLabel) == roles_.imu.end())
	{
		out_.ignored_entries++;
		return;
	}
	if (imu_label_ && *imu_label_ != o.sensorLabel)
		fail(at_entry() + "IMU observations with labels '" + *imu_label_ + "' and '" + o.sensorLabel +
			 "': choose one with [sensors] imu");
	imu_label_ = o.sensorLabel;
	using namespace mrpt::obs;
	for (TIMUDataIndex i : {IMU_X_ACC, IMU_Y_ACC, IMU_Z_ACC, IMU_WX, IMU_WY, IMU_WZ})
		if (!o.has(i)) fail(at_entry() + "CObservationIMU '" + o.sensorLabel + "' lacks field " + std::to_string(int(i)));
	if (!imu_sensor_pose_) imu_sensor_pose_ = o.sensorPose;
	RawImu r{o.timestamp, {o.get(IMU_X_ACC), o.get(IMU_Y_ACC), o.get(IMU_Z_ACC)}, {o.get(IMU_WX), o.get(IMU_WY), o.get(IMU_WZ)}};
	if (!r.acc.allFinite() || !r.gyro.allFinite()) fail(at_entry() + "non-finite IMU reading");
	imu_.push_back(r);
}

void ObservationReader::take_pose(const CObservationRobotPose& o)
{
	const bool is_odometry = std::find(roles_.odometry.begin(), roles_.odometry.end(), o.sensorLabel) != roles_.odometry.end();
	const bool is_prior = !is_odometry && (roles_.pose_prior.empty() || std::find(roles_.pose_prior.begin(), roles_.pose_prior.end(),
																					o.sensorLabel) != roles_.pose_prior.end());
	if (!is_odometry && !is_prior)
	{
		out_.ignored_entries++;
		return;
	}
	// A NaN would pass every check below and reach the estimators as a NaN residual.
	if (!o.pose.mean.asVectorVal().asEigen().allFinite() || !o.pose.mean.getRotationMatrix().asEigen().allFinite())
		fail(at_entry() + "pose of '" + o.sensorLabel + "' is not finite (x y z yaw pitch roll, degrees: " +
			 o.pose.mean.asString() + ")");
	const Matrix6d S = o.pose.cov.asEigen();
	if (!S.allFinite() || (S - S.transpose()).cwiseAbs().maxCoeff() > 1e-9 * std::max(1.0, S.cwiseAbs().maxCoeff()))
		fail(at_entry() + "covariance of '" + o.sensorLabel + "' is not finite and symmetric");
	Eigen::SelfAdjointEigenSolver<Matrix6d> es(0.5 * (S + S.transpose()));
	if (es.eigenvalues().minCoeff() <= 0)
		fail(at_entry() + "covariance of '" + o.sensorLabel + "' is not positive definite");
	// Read as priors by default only when one label is: a drifting odometry taken for a global prior gives
	// a wrong answer without an error.
	if (!is_odometry && roles_.pose_prior.empty() && !priors_.empty() && priors_.front().label != o.sensorLabel)
		fail(at_entry() + "CObservationRobotPose labels '" + priors_.front().label + "' and '" + o.sensorLabel +
			 "' would both be global pose priors: name the roles with [sensors] pose_prior and odometry "
			 "(e.g. --config with the .ini swba simulate-imu writes)");
	(is_odometry ? odometry_ : priors_).push_back({o.timestamp, o.sensorLabel, o.pose.mean, o.sensorPose, S, entry_});
}

void ObservationReader::take(const mrpt::serialization::CSerializable::Ptr& obj)
{
	const auto* obs = dynamic_cast<const mrpt::obs::CObservation*>(obj.get());
	if (!obs)
	{
		out_.ignored_entries++;
		return;
	}
	const std::string class_name = obs->GetRuntimeClass()->className;  // "mrpt::obs::CObservationIMU"
	labels_[class_name.substr(class_name.rfind(':') + 1)].insert(obs->sensorLabel);
	const std::string key = obs->GetRuntimeClass()->className + std::string("/") + obs->sensorLabel;
	auto it = last_ts_.find(key);
	if (it != last_ts_.end() && obs->timestamp < it->second)
		fail(at_entry() + "timestamps of '" + obs->sensorLabel + "' decrease");
	last_ts_[key] = obs->timestamp;
	if (!origin_ || obs->timestamp < *origin_) origin_ = obs->timestamp;
	if (const auto* imu = dynamic_cast<const CObservationIMU*>(obs))
		take_imu(*imu);
	else if (const auto* pose = dynamic_cast<const CObservationRobotPose*>(obs))
		take_pose(*pose);
	else
		out_.ignored_entries++;
}

/** The pose in the IMU frame (T·C, C = S⁻¹·I) and its tangent covariance A·J Σ Jᵀ·Aᵀ, J taken at
 * `covariance_at` (the pose itself for a prior, the increment for an odometry). */
PoseReading ObservationReader::to_imu_frame(const RawPose& p, const CPose3D& covariance_at) const
{
	const CPose3D C = (-p.sensor_pose) + imu_sensor_pose_.value_or(CPose3D());
	const Eigen::Matrix<double, 6, 6> A = right_factor_adjoint(C);
	const Eigen::Matrix<double, 6, 6> J = ypr_to_tangent_jacobian(covariance_at);
	PoseReading r;
	r.t = std::chrono::duration_cast<mrpt::Clock::duration>(p.ts - *origin_).count() * 1e-7;
	r.label = p.label;
	r.pose = p.pose + C;
	r.covariance = A * J * p.cov_ypr * J.transpose() * A.transpose();
	r.covariance = 0.5 * (r.covariance + r.covariance.transpose()).eval();
	return r;
}

void ObservationReader::convert()
{
	auto seconds = [this](mrpt::Clock::time_point ts) {
		return std::chrono::duration_cast<mrpt::Clock::duration>(ts - *origin_).count() * 1e-7;
	};
	for (const auto& r : imu_) out_.imu.push_back({seconds(r.ts), r.acc, r.gyro});
	for (const auto& p : priors_) out_.pose_priors.push_back(to_imu_frame(p, p.pose));
	std::map<std::string, CPose3D> previous;
	for (const auto& p : odometry_)
	{
		auto it = previous.find(p.label);
		const CPose3D increment = it == previous.end() ? p.pose : p.pose - it->second;  // prev⁻¹ ⊕ now
		out_.odometry.push_back(to_imu_frame(p, increment));
		previous[p.label] = p.pose;
	}
	auto by_time = [](const PoseReading& a, const PoseReading& b) { return a.t < b.t; };
	std::stable_sort(out_.pose_priors.begin(), out_.pose_priors.end(), by_time);
	std::stable_sort(out_.odometry.begin(), out_.odometry.end(), by_time);
	if (origin_) out_.time_origin = mrpt::Clock::toDouble(*origin_);
}

/** A gzip stream cut on an object boundary reads "cleanly": compare the reading with the scan. */
void ObservationReader::check_gzip_end(const detail::GuardedDecoder& decoder)
{
	const std::string fault = decoder.end_fault();
	if (!fault.empty()) fail("truncated gzip stream: " + fault + ", after " + std::to_string(entry_) + " entries");
	const std::string note = decoder.trailing_note();
	if (!note.empty()) out_.warnings.push_back(note);
}

/** Every object, decoded under the readers' guards (guarded_decoder.h), given to take(). */
void ObservationReader::read_objects()
{
	std::optional<detail::GuardedDecoder> decoder;
	try
	{
		decoder.emplace(out_.path, RawlogReaderOptions::kAutoMemoryBudget, true);
	}
	catch (const std::runtime_error& e)
	{
		fail(e.what());
	}
	for (bool clean_end = false;; entry_++)
	{
		mrpt::serialization::CSerializable::Ptr obj;
		const std::string damage = decoder->next(entry_, obj, clean_end);
		if (clean_end) break;
		if (!damage.empty()) fail(at_entry() + damage);
		out_.entries++;
		take(obj);
	}
	decoder->release();
	check_gzip_end(*decoder);
}

ObservationRawlog ObservationReader::run()
{
	try
	{
		roles_.validate();
	}
	catch (const std::invalid_argument& e)
	{
		fail(e.what());
	}
	check_input_file(out_.path, "rawlog");
	read_objects();
	check_role_labels(roles_.imu, "imu", "CObservationIMU");
	check_role_labels(roles_.pose_prior, "pose_prior", "CObservationRobotPose");
	check_role_labels(roles_.odometry, "odometry", "CObservationRobotPose");
	if (imu_.empty() && priors_.empty() && odometry_.empty())
		fail("no CObservationIMU or CObservationRobotPose with a role (" + std::to_string(out_.entries) + " entries)");
	convert();
	return out_;
}
}  // namespace

ObservationRawlog read_observation_rawlog(const std::string& path, const SensorRoles& roles)
{
	return ObservationReader(path, roles).run();
}
}  // namespace swba::io
