#include <swba/io/rawlog.h>

#include "guarded_decoder.h"

#include <swba/core/file.h>
#include <swba/core/memory_budget.h>

#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CActionRobotMovement3D.h>
#include <mrpt/obs/CObservation.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/filesystem.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>

namespace swba::io
{
namespace
{
using mrpt::obs::CActionCollection;
using mrpt::obs::CObservationBearingRange;
using mrpt::obs::CSensoryFrame;


bool finite_pose(const mrpt::poses::CPose3D& p)
{
	for (int i = 0; i < 6; i++)
		if (!std::isfinite(p[i])) return false;
	return true;
}

[[noreturn]] void fail_at(const std::string& at, const std::string& msg) { throw std::invalid_argument(at + ": " + msg); }

/** Why a reading is invalid, or nullptr; `own_noise`: its covariance must hold finite variances, those
 * of range and yaw > 0 (a 2D sensor's pitch variance may be 0). */
const char* invalid_reading(const CObservationBearingRange::TMeasurement& m, bool require_ids, bool own_noise)
{
	if (!std::isfinite(m.range)) return "non-finite range";
	if (m.range <= 0) return "range <= 0";
	if (!std::isfinite(m.yaw)) return "non-finite yaw";
	if (!std::isfinite(m.pitch)) return "non-finite pitch";
	if (require_ids && m.landmarkID < 0) return "landmarkID < 0 (unknown ID)";
	const auto& c = m.covariance;
	if (own_noise && !(c(0, 0) > 0 && c(1, 1) > 0 && c(2, 2) >= 0 && std::isfinite(c(0, 0) + c(1, 1) + c(2, 2))))
		return "its covariance (validCovariances) has a variance that is not finite, or not > 0 for range or yaw";
	return nullptr;
}

/** The reading's own σ from its covariance (validCovariances), whose correlations must be 0: the
 * estimators take a reading's noise as independent in range, yaw and pitch. */
void take_own_noise(const CObservationBearingRange::TMeasurement& m, RangeBearingReading& r, const std::string& what)
{
	const auto& c = m.covariance;
	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++)
			if (i != j && c(i, j) != 0)
				fail_at(what, "its covariance (validCovariances) correlates range, yaw and pitch; only per-reading "
							  "variances are supported (set the off-diagonal terms to 0)");
	r.std_range = std::sqrt(c(0, 0));
	r.std_yaw = std::sqrt(c(1, 1));
	r.std_pitch = std::sqrt(c(2, 2));
}

using Measurements = std::vector<CObservationBearingRange::TMeasurement>;

/** The first robot movement as the step's odometry, finite with non-negative variances; none: the
 * identity with a zero covariance. */
void read_odometry(const CActionCollection& acts, RawlogStep& s, const std::string& at)
{
	s.has_odometry = acts.getFirstMovementEstimation(s.odometry);
	if (!s.has_odometry)
	{
		s.odometry = mrpt::poses::CPose3DPDFGaussian();
		s.odometry.cov.setZero();
		return;
	}
	s.odometry_is_2d = !acts.getActionByClass<mrpt::obs::CActionRobotMovement3D>() &&
		acts.getActionByClass<mrpt::obs::CActionRobotMovement2D>();
	if (!finite_pose(s.odometry.mean)) fail_at(at, "odometry mean is not finite");
	for (int i = 0; i < 6; i++)
	{
		for (int j = 0; j < 6; j++)
			if (!std::isfinite(s.odometry.cov(i, j))) fail_at(at, "odometry covariance is not finite");
		if (s.odometry.cov(i, i) < 0) fail_at(at, "odometry covariance has a negative variance");
	}
}

/** The sensor pose and noise of a bearing-range observation, checked: the step's if it is the
 * frame's first, else they must equal the first's. */
void take_sensor(const CObservationBearingRange& br, RawlogStep& s, const std::string& at)
{
	const double stds[3] = {br.sensor_std_range, br.sensor_std_yaw, br.sensor_std_pitch};
	if (!finite_pose(br.sensorLocationOnRobot)) fail_at(at, "sensorLocationOnRobot is not finite");
	for (double v : stds)
		if (!std::isfinite(v) || v < 0) fail_at(at, "sensor_std_range/yaw/pitch must be finite and >= 0");
	if (!s.has_observation)
	{
		s.has_observation = true;
		s.sensor_pose = br.sensorLocationOnRobot;
		s.sensor_std_range = stds[0];
		s.sensor_std_yaw = stds[1];
		s.sensor_std_pitch = stds[2];
	}
	else if (
		!(br.sensorLocationOnRobot == s.sensor_pose) || stds[0] != s.sensor_std_range || stds[1] != s.sensor_std_yaw ||
		stds[2] != s.sensor_std_pitch)
	{
		fail_at(at, "several CObservationBearingRange with different sensor poses or noise in one sensory frame (not "
					"supported)");
	}
}

/** The valid readings of one observation, also appended to s.readings; invalid ones are counted in
 * s.skipped_readings and reported to `warn`. */
Measurements keep_valid_readings(const CObservationBearingRange& br, bool require_ids, RawlogStep& s,
								 const std::string& at, const std::function<void(const std::string&)>& warn)
{
	Measurements kept;
	for (std::size_t i = 0; i < br.sensedData.size(); i++)
	{
		const auto& m = br.sensedData[i];
		if (const char* why = invalid_reading(m, require_ids, br.validCovariances))
		{
			s.skipped_readings++;
			if (warn)
				warn(at + ": reading " + std::to_string(i) + " (landmark " + std::to_string(m.landmarkID) +
					 ") skipped: " + why);
			continue;
		}
		kept.push_back(m);
		s.readings.push_back({m.landmarkID, m.range, m.yaw, m.pitch});
		if (br.validCovariances) take_own_noise(m, s.readings.back(), at + ": reading " + std::to_string(i));
	}
	return kept;
}

/** A copy of the frame whose bearing-range observations (in order) hold `kept_per_obs`. */
CSensoryFrame::Ptr cleaned_frame(const CSensoryFrame& sf, const std::vector<Measurements>& kept_per_obs)
{
	auto clean = std::make_shared<CSensoryFrame>();
	std::size_t j = 0;
	for (const auto& o : sf)
	{
		if (o && IS_CLASS(*o, CObservationBearingRange))
		{
			auto c = std::make_shared<CObservationBearingRange>(dynamic_cast<const CObservationBearingRange&>(*o));
			c->sensedData = kept_per_obs[j++];
			clean->insert(c);
		}
		else
			clean->insert(o);
	}
	return clean;
}

class Reader
{
   public:
	Reader(const std::string& path, const RawlogReaderOptions& options) : opt_(options) { out_.path = path; }

	Rawlog run();

   private:
	[[noreturn]] void fail(const std::string& msg) const
	{
		throw std::runtime_error("rawlog '" + out_.path + "': " + msg);
	}
	void warn(const std::string& msg)
	{
		out_.warning_count++;
		if (out_.warnings.size() < opt_.max_warning_texts) out_.warnings.push_back(msg);
	}
	/** A truncated or corrupt file: an error, or (allow_truncated) a warning that ends the reading. */
	void truncated(const std::string& msg)
	{
		if (!opt_.allow_truncated) fail(msg);
		out_.truncated = true;
		warn(msg);
	}
	bool read_entry(detail::GuardedDecoder& decoder, bool& clean_end);
	void take_entry(const mrpt::serialization::CSerializable::Ptr& obj);
	void add_step(const CActionCollection::Ptr& acts, std::size_t act_entry, const CSensoryFrame::Ptr& sf,
				  std::size_t sf_entry);
	void check_gzip_end(const detail::GuardedDecoder& decoder);
	void check_contents() const;
	std::string where(std::size_t k, std::size_t act_entry, std::size_t sf_entry) const
	{
		return "step " + std::to_string(k) + " (rawlog entries " + std::to_string(act_entry) + "/" +
			std::to_string(sf_entry) + ")";
	}

	RawlogReaderOptions opt_;
	Rawlog out_;
	RawlogStepConverter converter_{opt_.require_landmark_ids};
	std::set<int32_t> ids_;
	std::size_t bare_observations_ = 0;
	CActionCollection::Ptr pending_;  ///< the last action collection, waiting for its sensory frame
	std::size_t pending_entry_ = 0;
	std::size_t entry_ = 0;  ///< entries read
};

void Reader::add_step(
	const CActionCollection::Ptr& acts, std::size_t act_entry, const CSensoryFrame::Ptr& sf, std::size_t sf_entry)
{
	RawlogStep s;
	try
	{
		s = converter_.convert(acts, sf, where(converter_.steps(), act_entry, sf_entry),
							   [this](const std::string& msg) { warn(msg); });
	}
	catch (const std::invalid_argument& e)
	{
		fail(e.what());
	}
	s.action_entry = act_entry;
	s.frame_entry = sf_entry;
	if (s.has_odometry) out_.steps_with_odometry++;
	if (s.has_odometry && s.odometry_is_2d) out_.steps_with_2d_odometry++;
	if (!s.has_observation) out_.steps_without_observation++;
	for (const auto& r : s.readings)
		if (r.landmark_id >= 0) ids_.insert(r.landmark_id);
	out_.readings += s.readings.size();
	out_.skipped_readings += s.skipped_readings;
	for (const auto& r : s.readings) out_.readings_with_own_noise += r.has_own_noise();
	out_.steps.push_back(std::move(s));
}

/** Reads and takes the next entry; false at the end of the data: clean (at an object boundary) or
 * after damage that allow_truncated lets pass. */
bool Reader::read_entry(detail::GuardedDecoder& decoder, bool& clean_end)
{
	mrpt::serialization::CSerializable::Ptr obj;
	const std::string damage = decoder.next(entry_, obj, clean_end);
	if (clean_end) return false;
	if (!damage.empty())
	{
		if (entry_ == 0) fail("not an MRPT rawlog, or corrupt from the start (entry 0: " + damage + ")");
		truncated("truncated or corrupt at entry " + std::to_string(entry_) + " after " +
				  std::to_string(out_.steps.size()) + " complete steps: " + damage);
		return false;
	}
	out_.entries++;
	take_entry(obj);
	entry_++;
	return true;
}

/** Pairs an action collection with the next sensory frame (as CRawlog::readActionObservationPair);
 * anything else is ignored. */
void Reader::take_entry(const mrpt::serialization::CSerializable::Ptr& obj)
{
	if (IS_CLASS(*obj, CActionCollection))
	{
		if (pending_)
		{
			out_.ignored_entries++;
			warn("entry " + std::to_string(pending_entry_) +
				 ": action collection without a following sensory frame, ignored (as MRPT's "
				 "readActionObservationPair does)");
		}
		pending_ = std::dynamic_pointer_cast<CActionCollection>(obj);
		pending_entry_ = entry_;
	}
	else if (IS_CLASS(*obj, CSensoryFrame) && pending_)
	{
		add_step(pending_, pending_entry_, std::dynamic_pointer_cast<CSensoryFrame>(obj), entry_);
		pending_.reset();
	}
	else
	{
		out_.ignored_entries++;
		if (IS_DERIVED(*obj, mrpt::obs::CObservation)) bare_observations_++;
	}
}

/** A gzip stream cut on an object boundary reads "cleanly": compare the reading with the scan. */
void Reader::check_gzip_end(const detail::GuardedDecoder& decoder)
{
	const std::string fault = decoder.end_fault();
	if (!fault.empty())
		truncated("truncated gzip stream: " + fault + ", after " + std::to_string(entry_) + " entries, " +
				  std::to_string(out_.steps.size()) + " complete steps");
	const std::string note = decoder.trailing_note();
	if (!note.empty()) warn(note);
}

/** Steps, odometry and valid readings must all be there. */
void Reader::check_contents() const
{
	const std::string counts = std::to_string(out_.entries) + " entries, " + std::to_string(out_.steps.size()) + " steps";
	if (out_.steps.empty())
	{
		if (bare_observations_ > 0)
			fail("no action/sensory-frame pairs (" + counts + "; " + std::to_string(bare_observations_) +
				 " bare observations: observation-only rawlogs are not supported)");
		fail("no action/sensory-frame pairs (" + counts + ")");
	}
	if (out_.steps_with_odometry == 0)
		fail("no odometry: none of the " + std::to_string(out_.steps.size()) +
			 " action collections holds a CActionRobotMovement2D/3D (" + counts + ")");
	if (out_.readings == 0)
	{
		std::string why = std::to_string(converter_.bearing_range_observations()) + " CObservationBearingRange, " +
			std::to_string(out_.skipped_readings) + " readings skipped as invalid";
		if (out_.skipped_readings > 0 && opt_.require_landmark_ids)
			why += "; the readings have no landmark ID (-1): use data association (--association auto, nn or jcbb) "
				   "instead of ids";
		fail("no valid bearing-range observation (" + counts + ", " + why + ")");
	}
}

Rawlog Reader::run()
{
	const std::string& path = out_.path;
	check_input_file(path, "rawlog");

	std::optional<detail::GuardedDecoder> decoder;
	try
	{
		decoder.emplace(path, opt_.memory_budget, opt_.probe_decoder);
	}
	catch (const std::runtime_error& e)
	{
		fail(e.what());
	}
	bool clean_end = false;
	while (!(opt_.max_steps && out_.steps.size() >= opt_.max_steps) && read_entry(*decoder, clean_end))
	{
	}
	decoder->release();
	if (pending_) out_.ignored_entries++;  // trailing action (normal in the kf-slam demos)
	if (clean_end) check_gzip_end(*decoder);
	check_contents();
	out_.distinct_landmarks = ids_.size();
	return std::move(out_);
}
}  // namespace

std::uint64_t auto_memory_budget(std::uint64_t data_bytes) { return scaled_memory_budget(data_bytes, 16); }

RawlogStep RawlogStepConverter::convert(const CActionCollection::Ptr& acts, const CSensoryFrame::Ptr& sf,
										const std::string& at, const std::function<void(const std::string&)>& warn)
{
	if (!acts) fail_at(at, "null action collection");
	if (!sf) fail_at(at, "null sensory frame");
	RawlogStep s;
	s.index = steps_;
	s.actions = acts;
	s.observations = sf;
	read_odometry(*acts, s, at);

	std::size_t br_count = 0;
	std::vector<Measurements> kept_per_obs;
	for (const auto& o : *sf)
	{
		if (!o || !IS_CLASS(*o, CObservationBearingRange)) continue;
		const auto& br = dynamic_cast<const CObservationBearingRange&>(*o);
		br_count++;
		take_sensor(br, s, at);
		kept_per_obs.push_back(keep_valid_readings(br, require_landmark_ids_, s, at, warn));
	}
	if (s.has_observation)
	{
		last_sensor_pose_ = s.sensor_pose;
		last_std_[0] = s.sensor_std_range;
		last_std_[1] = s.sensor_std_yaw;
		last_std_[2] = s.sensor_std_pitch;
	}
	else
	{
		s.sensor_pose = last_sensor_pose_;
		s.sensor_std_range = last_std_[0];
		s.sensor_std_yaw = last_std_[1];
		s.sensor_std_pitch = last_std_[2];
	}
	// Give every consumer (MRPT's EKF too) the same readings: a cleaned copy of the frame.
	if (s.skipped_readings > 0) s.observations = cleaned_frame(*sf, kept_per_obs);
	bearing_range_observations_ += br_count;
	steps_++;
	return s;
}

Rawlog read_rawlog(const std::string& path, const RawlogReaderOptions& options)
{
	Reader r(path, options);
	return r.run();
}

}  // namespace swba::io
