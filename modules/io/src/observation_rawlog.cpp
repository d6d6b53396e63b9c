#include <swba/io/observation_rawlog.h>

#include <swba/core/file.h>
#include <swba/core/lie.h>
#include <swba/io/rawlog.h>

#include "guarded_decoder.h"

#include <mrpt/io/CMemoryStream.h>
#include <mrpt/io/zip.h>
#include <mrpt/serialization/CArchive.h>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <sstream>
#include <stdexcept>

namespace swba::io
{
namespace
{
std::vector<std::string> split_labels(const std::string& text)
{
	std::vector<std::string> out;
	std::stringstream ss(text);
	std::string item;
	while (std::getline(ss, item, ','))
	{
		item.erase(std::remove_if(item.begin(), item.end(), [](unsigned char c) { return std::isspace(c); }), item.end());
		if (!item.empty()) out.push_back(item);
	}
	return out;
}

std::string join_labels(const std::vector<std::string>& v)
{
	std::string out;
	for (const auto& s : v) out += (out.empty() ? "" : ",") + s;
	return out;
}

bool contains(const std::vector<std::string>& v, const std::string& s) { return std::find(v.begin(), v.end(), s) != v.end(); }

IniKey<SensorRoles> labels_key(const std::string& section, const std::string& key, const std::string& meaning,
							   std::vector<std::string> SensorRoles::*field)
{
	return {section, key, "comma-separated labels", meaning,
			[field](const std::string& v, SensorRoles& o) { o.*field = split_labels(v); },
			[field](const SensorRoles& o) { return join_labels(o.*field); }};
}

mrpt::Clock::time_point time_at(double origin, double t)
{
	const auto ticks = static_cast<mrpt::Clock::rep>(std::llround(t * 1e7));
	return mrpt::Clock::fromDouble(origin) + mrpt::Clock::duration(ticks);
}
}  // namespace

void SensorRoles::validate() const
{
	for (const auto& l : pose_prior)
		if (contains(odometry, l))
			throw std::invalid_argument("sensor label '" + l + "' is both a pose prior and an odometry");
}

IniKeys<SensorRoles> SensorRoles::ini_keys(const std::string& section)
{
	return {
		labels_key(section, "imu", "CObservationIMU labels to use (empty: every IMU observation)", &SensorRoles::imu),
		labels_key(section, "pose_prior",
				   "CObservationRobotPose labels used as global pose priors (empty: every label not in odometry)",
				   &SensorRoles::pose_prior),
		labels_key(section, "odometry",
				   "CObservationRobotPose labels read as consecutive poses of a drifting odometry (relative motion only)",
				   &SensorRoles::odometry),
	};
}

Eigen::Matrix<double, 6, 6> right_factor_adjoint(const mrpt::poses::CPose3D& C)
{
	const Eigen::Matrix3d Rt = C.getRotationMatrix().asEigen().transpose();
	Eigen::Matrix<double, 6, 6> A = Eigen::Matrix<double, 6, 6>::Zero();
	A.topLeftCorner<3, 3>() = Rt;
	A.topRightCorner<3, 3>() = -Rt * skew(Eigen::Vector3d(C.x(), C.y(), C.z()));
	A.bottomRightCorner<3, 3>() = Rt;
	return A;
}

Eigen::Matrix<double, 6, 6> ypr_covariance_from_tangent(const mrpt::poses::CPose3D& at,
														const Eigen::Matrix<double, 6, 6>& tangent_covariance)
{
	const Eigen::Matrix<double, 6, 6> Jinv = ypr_to_tangent_jacobian(at).inverse();
	const Eigen::Matrix<double, 6, 6> S = Jinv * tangent_covariance * Jinv.transpose();
	return 0.5 * (S + S.transpose());
}

mrpt::obs::CObservationIMU::Ptr make_imu_observation(double origin, double t, const Eigen::Vector3d& acc,
													 const Eigen::Vector3d& gyro, const std::string& label)
{
	using namespace mrpt::obs;
	auto o = CObservationIMU::Create();
	o->timestamp = time_at(origin, t);
	o->sensorLabel = label;
	o->set(IMU_X_ACC, acc.x());
	o->set(IMU_Y_ACC, acc.y());
	o->set(IMU_Z_ACC, acc.z());
	o->set(IMU_WX, gyro.x());
	o->set(IMU_WY, gyro.y());
	o->set(IMU_WZ, gyro.z());
	return o;
}

mrpt::obs::CObservationRobotPose::Ptr make_pose_observation(double origin, double t, const mrpt::poses::CPose3D& pose,
															const Eigen::Matrix<double, 6, 6>& ypr_covariance,
															const std::string& label)
{
	auto o = mrpt::obs::CObservationRobotPose::Create();
	o->timestamp = time_at(origin, t);
	o->sensorLabel = label;
	o->pose.mean = pose;
	o->pose.cov.asEigen() = ypr_covariance;
	return o;
}

void write_observation_rawlog(const std::string& path, const std::vector<mrpt::obs::CObservation::Ptr>& objects)
{
	// Through the atomic writer (MRPT's gzip stream drops write errors): the objects are serialised in
	// chunks of about 8 MiB, each written as one gzip member; zlib's readers (CFileGZInputStream) read the
	// concatenated members as one stream.
	constexpr std::size_t kChunkBytes = std::size_t(8) << 20;
	write_file_atomically(
			path,
			[&](std::ostream& f) {
				mrpt::io::CMemoryStream chunk;
				auto arch = mrpt::serialization::archiveFrom(chunk);
				auto flush = [&] {
					if (chunk.getTotalBytesCount() == 0) return;
					const auto* begin = static_cast<const uint8_t*>(chunk.getRawBufferData());
					const std::vector<uint8_t> raw(begin, begin + chunk.getTotalBytesCount());
					std::vector<uint8_t> gz;
					if (!mrpt::io::zip::compress_gz_data_block(raw, gz, 1))
						throw std::runtime_error("rawlog '" + path + "': gzip compression failed");
					f.write(reinterpret_cast<const char*>(gz.data()), static_cast<std::streamsize>(gz.size()));
					chunk.clear();
				};
				for (const auto& o : objects)
				{
					arch << *o;
					if (chunk.getTotalBytesCount() >= kChunkBytes) flush();
				}
				flush();
			},
			std::ios::binary);
}

bool is_observation_rawlog(const std::string& path)
{
	check_input_file(path, "rawlog");
	// The first object of an untrusted file, decoded under the readers' guards: a corrupt count field
	// in it must not take the machine's memory before the reader proper can say what is wrong.
	std::string damage;
	mrpt::serialization::CSerializable::Ptr obj;
	try
	{
		detail::GuardedDecoder decoder(path, RawlogReaderOptions::kAutoMemoryBudget, true, 1);
		bool clean_end = false;
		damage = decoder.next(0, obj, clean_end);
	}
	catch (const std::runtime_error& e)
	{
		throw std::runtime_error("rawlog '" + path + "': " + e.what());
	}
	// Damage: not readable as either kind; the range-bearing reader says why.
	return damage.empty() && obj && IS_DERIVED(*obj, mrpt::obs::CObservation);
}
}  // namespace swba::io
