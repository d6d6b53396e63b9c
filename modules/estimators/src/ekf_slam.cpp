#include <swba/estimators/ekf_slam.h>

#include <swba/core/file.h>

#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/slam/CRangeBearingKFSLAM.h>
#include <mrpt/slam/CRangeBearingKFSLAM2D.h>
#include <mrpt/system/filesystem.h>
#include <mrpt/typemeta/TEnumType.h>

#include <chrono>
#include <type_traits>
#include <ctime>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace swba::estimators
{
namespace
{
double process_cpu_seconds()
{
	timespec ts{};
	clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
	return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

using Ekf3D = mrpt::slam::CRangeBearingKFSLAM;
using Ekf2D = mrpt::slam::CRangeBearingKFSLAM2D;

/** What differs between MRPT's 6D and 2D filters: the 2D one has no pitch noise and no z motion noise
 * (nullptr), and reports a CPose2D. */
float* pitch_std(Ekf3D& ekf) { return &ekf.options.std_sensor_pitch; }
float* pitch_std(Ekf2D&) { return nullptr; }
float* odo_z_std(Ekf3D& ekf) { return &ekf.options.std_odo_z_additional; }
float* odo_z_std(Ekf2D&) { return nullptr; }
mrpt::poses::CPose3D robot_pose(const Ekf3D& ekf) { return mrpt::poses::CPose3D(ekf.getCurrentRobotPoseMean()); }

/** The robot pose covariance in the tangent convention (quaternion_to_tangent_jacobian). */
PoseCovariance robot_covariance(const Ekf3D& ekf)
{
	mrpt::poses::CPose3DQuatPDFGaussian p;
	ekf.getCurrentRobotPose(p);
	const Eigen::Matrix<double, 6, 7> J = quaternion_to_tangent_jacobian(p.mean);
	const PoseCovariance c = J * p.cov.asEigen() * J.transpose();
	return 0.5 * (c + c.transpose());
}
/** 2D: (x, y, φ) to (ρx, ρy, ωz) = (R(φ)ᵀ Δt, Δφ), embedded at rows (0, 1, 5). */
PoseCovariance robot_covariance(const Ekf2D& ekf)
{
	mrpt::poses::CPosePDFGaussian p;
	ekf.getCurrentRobotPose(p);
	Eigen::Matrix3d J = Eigen::Matrix3d::Identity();
	const double c = std::cos(p.mean.phi()), s = std::sin(p.mean.phi());
	J.topLeftCorner<2, 2>() << c, s, -s, c;
	const Eigen::Matrix3d C = J * p.cov.asEigen() * J.transpose();
	PoseCovariance out = PoseCovariance::Zero();
	const int at[3] = {0, 1, 5};
	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++) out(at[i], at[j]) = 0.5 * (C(i, j) + C(j, i));
	return out;
}

/** The filter's map: mean and covariance block of each landmark, by ID. */
template <class Ekf>
std::map<std::int32_t, LandmarkEstimate> final_landmarks(const Ekf& ekf)
{
	constexpr bool planar = std::is_same_v<Ekf, Ekf2D>;
	constexpr int robot = planar ? 3 : 7, dim = planar ? 2 : 3;
	std::conditional_t<planar, mrpt::poses::CPosePDFGaussian, mrpt::poses::CPose3DQuatPDFGaussian> pose;
	std::vector<std::conditional_t<planar, mrpt::math::TPoint2D, mrpt::math::TPoint3D>> points;
	std::map<unsigned int, mrpt::maps::CLandmark::TLandmarkID> ids;
	mrpt::math::CVectorDouble state;
	mrpt::math::CMatrixDouble cov;
	ekf.getCurrentState(pose, points, ids, state, cov);
	std::map<std::int32_t, LandmarkEstimate> out;
	for (const auto& [index, id] : ids)
	{
		LandmarkEstimate& e = out[static_cast<std::int32_t>(id)];
		const int at = robot + dim * static_cast<int>(index);
		for (int i = 0; i < dim; i++)
		{
			e.position[i] = state[at + i];  // = points[index] (the filter's own copy)
			for (int j = 0; j < dim; j++) e.covariance(i, j) = 0.5 * (cov(at + i, at + j) + cov(at + j, at + i));
		}
	}
	return out;
}
mrpt::poses::CPose3D robot_pose(const Ekf2D& ekf)
{
	mrpt::poses::CPosePDFGaussian p;
	ekf.getCurrentRobotPose(p);
	return mrpt::poses::CPose3D(p.mean);
}

void add_note(EkfSlamResult& res, const std::string& note)
{
	res.notes += (res.notes.empty() ? "" : "; ") + note;
}

/** Throws unless v is finite and > 0; returns v. */
double checked_positive(double v, const char* what)
{
	if (!(v > 0) || !std::isfinite(v))
		throw std::invalid_argument(std::string("EKF option ") + what + " must be finite and > 0");
	return v;
}

/** The filter's options before the overrides: the INI file if given, else kfEKFAlaDavison with the
 * sensor noise of the first step that has a bearing-range observation (a zero std there keeps MRPT's
 * default and is noted in res.notes). */
template <class Ekf>
void load_base_options(Ekf& ekf, const std::vector<io::RawlogStep>& steps,
					   const EkfSlamOptions& options, EkfSlamResult& res)
{
	std::size_t own = 0;
	for (const auto& s : steps)
		for (const auto& r : s.readings) own += r.has_own_noise();
	if (own > 0)
		add_note(res, std::to_string(own) + " readings carry their own covariance (validCovariances): MRPT's EKF "
				 "takes one sensor noise for every reading (sensor_std_*, or the options'), not theirs");
	if (!options.ini_file.empty())
	{
		// Read as text first: a missing, binary or non-regular file is named, not parsed as an empty INI.
		ekf.loadOptions(mrpt::config::CConfigFileMemory(read_text_file(options.ini_file, "EKF INI file")));
		return;
	}
	ekf.KF_options.method = mrpt::bayes::TKFMethod::kfEKFAlaDavison;
	const io::RawlogStep* with_obs = nullptr;
	for (const auto& s : steps)
		if (s.has_observation)
		{
			with_obs = &s;
			break;
		}
	if (!with_obs) return;
	// A zero std means "not given" (2D sensors have sensor_std_pitch = 0): keep MRPT's default, and say
	// so unless an explicit option (apply_overrides) replaces it.
	auto take = [&res](double v, float& dst, const char* name, bool overridden) {
		if (v > 0)
			dst = static_cast<float>(v);
		else if (!overridden)
			add_note(res, std::string("the observation's ") + name + " is 0: MRPT's default kept");
	};
	take(with_obs->sensor_std_range, ekf.options.std_sensor_range, "sensor_std_range", options.std_range.has_value());
	take(with_obs->sensor_std_yaw, ekf.options.std_sensor_yaw, "sensor_std_yaw", options.std_yaw.has_value());
	if (float* pitch = pitch_std(ekf))
		take(with_obs->sensor_std_pitch, *pitch, "sensor_std_pitch", options.std_pitch.has_value());
}

/** The explicit options over the INI / defaults, validated; the values used are recorded in `res`.
 * The 2D filter has no pitch and no z motion noise: those options are not used (noted). */
template <class Ekf>
void apply_overrides(Ekf& ekf, const EkfSlamOptions& options, EkfSlamResult& res)
{
	using mrpt::bayes::TKFMethod;
	if (options.method) ekf.KF_options.method = static_cast<TKFMethod>(ekf_method_from_name(*options.method));
	if (options.std_range)
		ekf.options.std_sensor_range = static_cast<float>(checked_positive(*options.std_range, "std_range"));
	if (options.std_yaw) ekf.options.std_sensor_yaw = static_cast<float>(checked_positive(*options.std_yaw, "std_yaw"));
	float* pitch = pitch_std(ekf);
	if (options.std_pitch && pitch) *pitch = static_cast<float>(checked_positive(*options.std_pitch, "std_pitch"));
	if (options.std_pitch && !pitch) add_note(res, "std_pitch not used by the 2D filter");
	if (options.std_odo_z_additional_m)
	{
		if (!(*options.std_odo_z_additional_m >= 0))
			throw std::invalid_argument("EKF option std_odo_z_additional_m must be >= 0");
		if (float* z = odo_z_std(ekf))
			*z = static_cast<float>(*options.std_odo_z_additional_m);
		else
			add_note(res, "std_odo_z_additional_m not used by the 2D filter");
	}
	if (options.data_association)
	{
		if (*options.data_association != "nn" && *options.data_association != "jcbb")
			throw std::invalid_argument("EKF option data_association must be nn or jcbb, got '" +
										*options.data_association + "'");
		ekf.options.data_assoc_method =
			*options.data_association == "jcbb" ? mrpt::slam::assocJCBB : mrpt::slam::assocNN;
	}
	checked_positive(ekf.options.std_sensor_range, "std_range");
	checked_positive(ekf.options.std_sensor_yaw, "std_yaw");
	if (pitch) checked_positive(*pitch, "std_pitch");

	res.method = mrpt::typemeta::TEnumType<TKFMethod>::value2name(ekf.KF_options.method);
	res.std_range = ekf.options.std_sensor_range;
	res.std_yaw = ekf.options.std_sensor_yaw;
	res.std_pitch = pitch ? *pitch : 0.0;
}

/** Silence (no console logging, no profiler table) unless verbose; warnings are counted in `res`
 * through a callback, so `res` must outlive the filter. */
template <class Ekf>
void route_mrpt_log(Ekf& ekf, const EkfSlamOptions& options, EkfSlamResult& res)
{
	if (!options.mrpt_verbose)
	{
		ekf.logging_enable_console_output = false;
		ekf.setMinLoggingLevel(mrpt::system::LVL_WARN);
		ekf.getProfiler().enable(false);
	}
	ekf.logRegisterCallback([&res](std::string_view msg, const mrpt::system::VerbosityLevel level,
								   std::string_view, const mrpt::Clock::time_point) {
		if (level < mrpt::system::LVL_WARN) return;
		if (res.mrpt_warnings++ == 0) res.first_mrpt_warning = io::mrpt_exception_summary(std::string(msg));
	});
}

/** The landmark each reading of `step` went to in the filter's last update (EkfSlamResult::assigned_ids):
 * MRPT's data association maps reading j to a landmark index (data_association_full_covariance is given
 * the predictions' landmark indices, predictions_IDs, and returns those) or inserts a landmark from it. */
template <class Ekf>
std::vector<std::int32_t> assigned_landmarks(const Ekf& ekf, const io::RawlogStep& step)
{
	const auto& da = ekf.getLastDataAssociation();
	std::vector<std::int32_t> ids;
	for (std::size_t j = 0; j < step.readings.size(); j++)
	{
		std::int32_t id = step.readings[j].landmark_id;
		if (id < 0)
		{
			const auto a = da.results.associations.find(j);
			const auto n = da.newly_inserted_landmarks.find(j);
			if (a != da.results.associations.end())
				id = static_cast<std::int32_t>(a->second);
			else if (n != da.newly_inserted_landmarks.end())
				id = static_cast<std::int32_t>(n->second);
		}
		ids.push_back(id);
	}
	return ids;
}

/** Feeds the first n steps to the filter, recording each pose and the time spent inside
 * processActionObservation; stops at (and records) the first failure. */
template <class Ekf>
void process_steps(Ekf& ekf, const std::vector<io::RawlogStep>& steps, std::size_t n,
				   const EkfSlamOptions& options, EkfSlamResult& res)
{
	res.times.reserve(n);
	res.poses.reserve(n);
	double seconds = 0, cpu_seconds = 0;
	for (std::size_t k = 0; k < n; k++)
	{
		mrpt::obs::CActionCollection::Ptr acts = steps[k].actions;
		mrpt::obs::CSensoryFrame::Ptr sf = steps[k].observations;
		if (!acts || !sf)
		{
			res.failed = true;
			res.failed_step = k;
			res.failure = "step " + std::to_string(k) + " has no action collection or sensory frame";
			break;
		}
		const auto t0 = std::chrono::steady_clock::now();
		const double c0 = process_cpu_seconds();
		const auto add_time = [&] {
			seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
			cpu_seconds += process_cpu_seconds() - c0;
		};
		try
		{
			ekf.processActionObservation(acts, sf);
		}
		catch (const std::exception& e)
		{
			add_time();
			res.failed = true;
			res.failed_step = k;
			res.failure = io::mrpt_exception_summary(e.what());
			res.failure_details = e.what();
			break;
		}
		add_time();
		res.times.push_back(steps[k].time());
		res.poses.push_back(robot_pose(ekf));
		res.covariances.push_back(robot_covariance(ekf));
		res.assigned_ids.push_back(assigned_landmarks(ekf, steps[k]));
		res.steps_processed++;
		if (options.progress) options.progress(k + 1, n);
	}
	res.seconds = seconds;
	res.ms_per_step = res.steps_processed ? 1e3 * seconds / double(res.steps_processed) : 0.0;
	res.cpu_seconds = cpu_seconds;
	res.cpu_ms_per_step = res.steps_processed ? 1e3 * cpu_seconds / double(res.steps_processed) : 0.0;
}
}  // namespace

Eigen::Matrix<double, 6, 7> quaternion_to_tangent_jacobian(const mrpt::poses::CPose3DQuat& mean)
{
	const auto& q = mean.quat();
	const double w = q.r();
	const Eigen::Vector3d v(q.x(), q.y(), q.z());
	Eigen::Matrix3d vx;
	vx << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
	Eigen::Matrix<double, 6, 7> J = Eigen::Matrix<double, 6, 7>::Zero();
	mrpt::math::CMatrixDouble33 R;
	q.rotationMatrixNoResize(R);
	J.block<3, 3>(0, 0) = R.asEigen().transpose();
	J.block<3, 1>(3, 3) = -2 * v;
	J.block<3, 3>(3, 4) = 2 * (w * Eigen::Matrix3d::Identity() - vx);
	return J;
}

int ekf_method_from_name(const std::string& name)
{
	// The names are MRPT's own (TEnumType of TKFMethod); MRPT's INI reader also takes the number.
	using mrpt::bayes::TKFMethod;
	using Names = mrpt::typemeta::TEnumType<TKFMethod>;
	// kfIKF (3) is refused: MRPT 2.5 throws "IKF scalar by scalar not implemented yet" at its first update.
	constexpr int kMethods = 3;
	if (name == Names::value2name(TKFMethod::kfIKF) || name == "3")
		throw std::invalid_argument("EKF method '" + name + "' is not implemented by MRPT (its scalar-by-scalar IKF "
									"throws at the first update): use kfIKFFull");
	std::string expected;
	for (int i = 0; i < kMethods; i++)
	{
		const std::string known = Names::value2name(static_cast<TKFMethod>(i));
		if (name == known || name == std::to_string(i)) return i;
		expected += (i == 0 ? "" : i + 1 == kMethods ? " or " : ", ") + known;
	}
	throw std::invalid_argument("unknown EKF method '" + name + "' (expected " + expected + ")");
}

namespace
{
template <class Ekf>
void run_filter(const std::vector<io::RawlogStep>& steps, std::size_t n, const EkfSlamOptions& options,
				EkfSlamResult& res)
{
	Ekf ekf;
	load_base_options(ekf, steps, options, res);
	apply_overrides(ekf, options, res);
	route_mrpt_log(ekf, options, res);
	process_steps(ekf, steps, n, options, res);
	res.landmarks = ekf.getNumberOfLandmarksInTheMap();
	res.landmarks_final = final_landmarks(ekf);
}
}  // namespace

EkfSlamResult run_ekf_slam(const std::vector<io::RawlogStep>& steps, const EkfSlamOptions& options)
{
	EkfSlamResult res;
	if (steps.empty()) throw std::invalid_argument("run_ekf_slam: no steps");
	const std::size_t n = options.max_steps ? std::min(options.max_steps, steps.size()) : steps.size();
	res.steps_total = n;
	res.model = resolve_pose_model(options.model, steps);
	if (res.model == PoseModel::Planar)
		run_filter<Ekf2D>(steps, n, options, res);
	else
		run_filter<Ekf3D>(steps, n, options, res);
	return res;
}
}  // namespace swba::estimators
