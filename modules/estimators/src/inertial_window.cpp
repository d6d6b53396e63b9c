#include <swba/estimators/inertial_window.h>

#include "inertial_gauge.h"

#include <swba/core/manifold.h>
#include <swba/factors/between_pose.h>
#include <swba/factors/body_velocity_prior.h>
#include <swba/factors/imu_factor.h>
#include <swba/factors/pose_prior.h>
#include <swba/smoother/fixed_lag_smoother.h>

#include <Eigen/LU>
#include <swba/core/timing.h>
#include <algorithm>
#include <cmath>
#include <deque>
#include <optional>
#include <stdexcept>
#include <string>

namespace swba::estimators
{
namespace
{
struct Relative
{
	mrpt::poses::CPose3D D;
	Matrix6d covariance;
};

/** What a keyframe brings: its time, its pose prior and the odometry increment from the previous one. */
struct KeyframeData
{
	double t = 0;
	std::optional<io::PoseReading> prior;
	std::optional<Relative> relative;
};

/** The reading at time t (within 1 µs), if any; `readings` in time order. */
std::optional<std::size_t> reading_at(const std::vector<io::PoseReading>& readings, double t)
{
	const auto it = std::lower_bound(readings.begin(), readings.end(), t - 1e-6,
									 [](const io::PoseReading& r, double x) { return r.t < x; });
	if (it == readings.end() || std::abs(it->t - t) >= 1e-6) return std::nullopt;
	return static_cast<std::size_t>(it - readings.begin());
}

/** The increments a→b of the odometry composed, D = D_{a+1}·…·D_b, with covariance moved into D's tangent
 * step by step: D·Exp(δ)·D_k = (D·D_k)·Exp(A_k δ), A_k = right_factor_adjoint(D_k). */
Relative composed_increment(const std::vector<io::PoseReading>& odo, std::size_t a, std::size_t b)
{
	Relative r{mrpt::poses::CPose3D(), Matrix6d::Zero()};
	for (std::size_t k = a + 1; k <= b; k++)
	{
		const mrpt::poses::CPose3D Dk = odo[k].pose - odo[k - 1].pose;
		const Matrix6d A = io::right_factor_adjoint(Dk);
		r.D = r.D + Dk;
		r.covariance = A * r.covariance * A.transpose() + odo[k].covariance;
	}
	return r;
}

std::vector<KeyframeData> keyframes(const InertialInput& in, const InertialFilterOptions& o, double t0)
{
	std::vector<KeyframeData> out;
	std::optional<std::size_t> prev_odo;
	for (const double t : inertial_report_times(in, o.keyframes))
	{
		if (t < t0 || t > in.imu.back().t) continue;
		KeyframeData k;
		k.t = t;
		const std::optional<std::size_t> prior = reading_at(in.pose_priors, t);
		if (prior && (o.use_pose_priors || out.empty())) k.prior = in.pose_priors[*prior];
		const std::optional<std::size_t> odo = o.use_odometry ? reading_at(in.odometry, k.t) : std::nullopt;
		if (odo && prev_odo && !out.empty()) k.relative = composed_increment(in.odometry, *prev_odo, *odo);
		if (odo) prev_odo = odo;
		out.push_back(std::move(k));
	}
	return out;
}

/** The readings from t_i to t_j: interpolated at both ends, every reading strictly inside. */
std::vector<ImuSample> interval_samples(const std::vector<ImuSample>& imu, std::size_t& cursor, double ti, double tj)
{
	while (cursor + 1 < imu.size() && imu[cursor + 1].t <= ti) cursor++;
	std::vector<ImuSample> s{interpolate_imu(imu[cursor], imu[std::min(cursor + 1, imu.size() - 1)], ti)};
	std::size_t k = cursor + 1;
	for (; k < imu.size() && imu[k].t < tj; k++)
		if (imu[k].t > ti) s.push_back(imu[k]);
	s.push_back(interpolate_imu(imu[k - 1], imu[std::min(k, imu.size() - 1)], tj));
	return s;
}

Matrix6d information(const Matrix6d& covariance) { return covariance.inverse(); }

mrpt::poses::CPose3D make_pose(const NavState& x) { return SE3Manifold::to_pose(x.R, x.p); }

/** The window's factor graph on the smoother, and the smoother's client. */
class InertialGraph : smoother::SmootherClient
{
   public:
	InertialGraph(const InertialWindowOptions& o, const InertialInput& in, int lag)
		: o_(o), in_(in), sm_(smoother_options(o, lag))
	{
	}

	void add_first(const InertialInitialState& init, const KeyframeData& k);
	/** Adds keyframe k; its initial value is the IMU prediction from the previous keyframe, or `guess`. */
	void add_next(const KeyframeData& k, const std::optional<std::pair<NavState, Vector6d>>& guess = std::nullopt);
	/** The smoother's update(): the online record, re-integration of the IMU factors whose bias moved,
	 * and the oldest keyframe recorded in `lagged` and marginalised when the window is full. */
	void update(InertialTrajectory& online, InertialTrajectory& lagged);
	void record_all(InertialTrajectory& out) const;
	Summary solve(const SolverOptions& s)
	{
		const detail::InertialGaugeReference before = gauge_reference();
		anchor_gauge(before);
		const Summary r = swba::solve(sm_.problem(), s);
		hold_gauge(before);
		return r;
	}
	/** Re-integrates the IMU factors whose bias moved (after a solve). */
	std::size_t reintegrate_moved()
	{
		const std::size_t before = reintegrations;
		reintegrate();
		return reintegrations - before;
	}
	/** Sets the first keyframe's velocity and biases (the batch's initial values). */
	void set_first(const NavState& x, const Vector6d& b);
	std::size_t reintegrations = 0, relative_factors = 0, prior_factors = 0;

   private:
	struct Kf
	{
		double t;
		VariableId T, v, b;
		FactorId imu = -1;
		std::shared_ptr<const ImuPreintegration> pim;
	};
	static smoother::FixedLagSmootherOptions smoother_options(const InertialWindowOptions& o, int lag)
	{
		smoother::FixedLagSmootherOptions s;
		s.window = lag;
		s.first_estimate_jacobians = o.first_estimate_jacobians;
		s.solver = o.solver;
		s.marginalization_threshold = o.marginalization_threshold;
		return s;
	}
	NavState nav(const Kf& k) const;
	Vector6d bias(const Kf& k) const { return Eigen::Map<const Vector6d>(sm_.problem().value(k.b)); }
	void add_pose_prior(const Kf& k, const mrpt::poses::CPose3D& Z, const Matrix6d& covariance);
	/** The smoother's add_factor, through TiltFactor for the factors on a fixed gauge's first pose. */
	FactorId add_factor(std::shared_ptr<const Factor> f, const std::vector<VariableId>& vars);
	/** The first keyframe's pose: on TiltManifold under the fixed four-DoF gauge. */
	VariableId add_first_pose(const NavState& x);
	detail::InertialGaugeReference gauge_reference() const;
	/** Anchors the four directions on `before` for the next solve (free gauge only). */
	void anchor_gauge(const detail::InertialGaugeReference& before);
	/** Removes the anchor and undoes the four-DoF motion since `before` (free gauge only). */
	void hold_gauge(const detail::InertialGaugeReference& before);
	void record(InertialTrajectory& out, const Kf& k, const Matrix6d& covariance) const;
	/** A covariance block of k's pose in the SE(3) tangent (6×6, or 2×2 on the fixed gauge's TiltManifold). */
	Matrix6d pose_covariance(const Kf& k, const Eigen::MatrixXd& block) const;
	void reintegrate();
	// SmootherClient: the oldest keyframe leaves with its velocity and biases.
	bool hold(const smoother::UpdateSummary& u) override;  ///< the free gauge's hold
	void solved(const smoother::UpdateSummary& u) override;
	std::set<VariableId> leaving(const smoother::TimedState&) override { return {kfs_.front().v, kfs_.front().b}; }
	void left(const smoother::TimedState&, const std::vector<double>&) override
	{
		record(*lagged_, kfs_.front(), Matrix6d::Zero());
	}
	void marginalized(const smoother::TimedState&, const smoother::MarginalizationSummary&) override;
	InertialTrajectory* online_ = nullptr;
	InertialTrajectory* lagged_ = nullptr;
	detail::InertialGaugeReference before_;  ///< the free gauge's reference before this update's solve
	FactorId anchor_ = -1;					 ///< the free gauge's anchor during a solve

	InertialWindowOptions o_;
	const InertialInput& in_;
	smoother::FixedLagSmoother sm_;
	std::deque<Kf> kfs_;
	std::size_t cursor_ = 0;
	GaugeMode gauge_ = GaugeMode::Prior;  ///< o_.gauge without pose priors, else Prior (the priors fix the frame)
	VariableId tilt_pose_ = -1;			  ///< the fixed gauge's first pose
	VariableId reference_ = -1;			  ///< the free gauge's frame: the first pose, never marginalised
};

NavState InertialGraph::nav(const Kf& k) const
{
	NavState x;
	const auto T = se3_view(sm_.problem().value(k.T));
	x.R = T.leftCols<3>();
	x.p = T.col(3);
	x.v = Eigen::Map<const Eigen::Vector3d>(sm_.problem().value(k.v));
	return x;
}

void InertialGraph::add_pose_prior(const Kf& k, const mrpt::poses::CPose3D& Z, const Matrix6d& covariance)
{
	auto f = std::make_shared<PosePriorFactor>(Z);
	f->set_information(information(covariance));
	add_factor(f, {k.T});
	prior_factors++;
}

void InertialGraph::add_first(const InertialInitialState& init, const KeyframeData& k)
{
	Problem& p = sm_.problem();
	if (!k.prior) gauge_ = o_.gauge;
	Kf kf{k.t, add_first_pose(init.x), p.add_variable(Eigen::VectorXd(init.x.v), euclidean_manifold(3)),
		  p.add_variable(Eigen::VectorXd(init.bias), euclidean_manifold(6)), -1, nullptr};
	// The free gauge's frame is the first keyframe's: its pose stays in the model when the keyframe leaves
	// (its velocity is the state the smoother marginalises), so that the prior keeps every later keyframe's
	// relation to it. It adds no information along the four directions: every factor is invariant there.
	if (gauge_ == GaugeMode::Free) reference_ = kf.T;
	sm_.add_state(k.t, gauge_ == GaugeMode::Free ? kf.v : kf.T);
	if (k.prior)
		add_pose_prior(kf, k.prior->pose, k.prior->covariance);
	else if (gauge_ != GaugeMode::Prior)
	{
		auto f = std::make_shared<PosePriorFactor>(make_pose(init.x));  // roll and pitch only
		f->set_sqrt_information(detail::tilt_prior_sqrt_information(init.x.R, o_.measurements.prior.odometry_tilt_sigma));
		add_factor(f, {kf.T});
	}
	else
	{
		const Eigen::Matrix3d Rt = init.x.R.transpose();
		Matrix6d A = Matrix6d::Identity();	// the filter's [δp (world), δφ] to the manifold's [ρ (body), ω]
		A.topLeftCorner<3, 3>() = Rt;
		add_pose_prior(kf, make_pose(init.x), A * init.P.topLeftCorner<6, 6>() * A.transpose());
	}
	if (gauge_ == GaugeMode::Free)
	{
		// In the body frame: a prior on the world velocity would inform the heading (|v_h|²/σ_v²).
		auto pv = std::make_shared<BodyVelocityPriorFactor>(init.x.R.transpose() * init.x.v);
		pv->set_information(init.x.R.transpose() * init.P.block<3, 3>(6, 6).inverse() * init.x.R);
		sm_.add_factor(pv, {kf.T, kf.v});
	}
	else
	{
		auto pv = std::make_shared<EuclideanPriorFactor>(Eigen::VectorXd(init.x.v));
		pv->set_information(init.P.block<3, 3>(6, 6).inverse());
		sm_.add_factor(pv, {kf.v});
	}
	auto pb = std::make_shared<EuclideanPriorFactor>(Eigen::VectorXd(init.bias));
	pb->set_information(init.P.block<6, 6>(9, 9).inverse());
	sm_.add_factor(pb, {kf.b});
	kfs_.push_back(kf);
}

void InertialGraph::add_next(const KeyframeData& k, const std::optional<std::pair<NavState, Vector6d>>& guess)
{
	const Kf& prev = kfs_.back();
	const Vector6d b = bias(prev);
	auto pim = std::make_shared<ImuPreintegration>(o_.measurements.noise, b);
	for (const ImuSample& s : interval_samples(in_.imu, cursor_, prev.t, k.t)) pim->add_sample(s);
	const NavState x = guess ? guess->first : pim->predict(nav(prev), b);
	const Vector6d bj = guess ? guess->second : b;
	Problem& p = sm_.problem();
	Kf kf{k.t, p.add_pose(make_pose(x)), p.add_variable(Eigen::VectorXd(x.v), euclidean_manifold(3)),
		  p.add_variable(Eigen::VectorXd(bj), euclidean_manifold(6)), -1, nullptr};
	kf.pim = pim;
	sm_.add_state(k.t, kf.T);
	kf.imu = add_factor(std::make_shared<ImuPreintegrationFactor>(pim), {prev.T, prev.v, prev.b, kf.T, kf.v, kf.b});
	if (k.prior) add_pose_prior(kf, k.prior->pose, k.prior->covariance);
	if (k.relative)
	{
		auto f = std::make_shared<BetweenPoseFactor>(k.relative->D);
		f->set_information(information(k.relative->covariance));
		add_factor(f, {prev.T, kf.T});
		relative_factors++;
	}
	kfs_.push_back(kf);
}

FactorId InertialGraph::add_factor(std::shared_ptr<const Factor> f, const std::vector<VariableId>& vars)
{
	for (std::size_t i = 0; i < vars.size(); i++)
		if (vars[i] == tilt_pose_) f = std::make_shared<detail::TiltFactor>(f, static_cast<int>(i));
	return sm_.add_factor(std::move(f), vars);
}

VariableId InertialGraph::add_first_pose(const NavState& x)
{
	if (gauge_ != GaugeMode::Fixed) return sm_.problem().add_pose(make_pose(x));
	double v[SE3Manifold::kAmbient];
	SE3Manifold::from_pose(make_pose(x), v);
	tilt_pose_ = sm_.problem().add_variable(v, detail::TiltManifold::instance());
	return tilt_pose_;
}

detail::InertialGaugeReference InertialGraph::gauge_reference() const
{
	// The reference pose at its first estimate, where the prior's null space is the gauge (its current
	// value until the first marginalisation freezes it).
	detail::InertialGaugeReference r;
	if (gauge_ != GaugeMode::Free || reference_ < 0) return r;
	const VariableId id = reference_;
	const double* x = sm_.linearization_point(id);
	r.id = id;
	r.pose.assign(x, x + SE3Manifold::kAmbient);
	return r;
}

void InertialGraph::anchor_gauge(const detail::InertialGaugeReference& before)
{
	if (before.id < 0) return;
	// Straight into the problem, not through the smoother's add_factor: it is no measurement, it is removed
	// (hold_gauge) before anything is marginalised, and its Jacobian at its own Z needs no first estimate.
	anchor_ = sm_.problem().add_factor(detail::inertial_gauge_anchor(before), {before.id});
}

void InertialGraph::hold_gauge(const detail::InertialGaugeReference& before)
{
	if (gauge_ != GaugeMode::Free) return;
	if (anchor_ >= 0) sm_.problem().remove_factor(anchor_);
	anchor_ = -1;
	std::vector<std::pair<VariableId, VariableId>> window;
	if (kfs_.empty() || kfs_.front().T != reference_) window.push_back({reference_, -1});  // its keyframe left
	for (const Kf& k : kfs_) window.push_back({k.T, k.v});
	detail::hold_inertial_gauge(sm_.problem(), before, window);
}

void InertialGraph::record(InertialTrajectory& out, const Kf& k, const Matrix6d& covariance) const
{
	const NavState x = nav(k);
	out.t.push_back(k.t);
	out.poses.push_back(make_pose(x));
	out.velocities.push_back(x.v);
	out.biases.push_back(bias(k));
	out.pose_covariances.push_back(covariance);
}

void InertialGraph::update(InertialTrajectory& online, InertialTrajectory& lagged)
{
	CovarianceRequest request;
	if (o_.covariances && gauge_ != GaugeMode::Free) request.groups.push_back({kfs_.back().T});
	online_ = &online;
	lagged_ = &lagged;
	before_ = gauge_reference();
	anchor_gauge(before_);
	sm_.update(*this, request);
}

bool InertialGraph::hold(const smoother::UpdateSummary&)
{
	if (gauge_ != GaugeMode::Free) return false;
	hold_gauge(before_);
	return true;
}

Matrix6d InertialGraph::pose_covariance(const Kf& k, const Eigen::MatrixXd& block) const
{
	if (block.rows() == 6) return block;
	// The fixed gauge's first pose lives on TiltManifold: its 2×2 block mapped to the SE(3) tangent.
	const Eigen::Matrix<double, 6, 2> B = detail::TiltManifold::basis(sm_.problem().value(k.T));
	return B * block * B.transpose();
}

void InertialGraph::solved(const smoother::UpdateSummary& u)
{
	const bool ok = o_.covariances && u.covariance.ok && !u.covariance.blocks.empty();
	record(*online_, kfs_.back(), ok ? pose_covariance(kfs_.back(), u.covariance.blocks[0]) : Matrix6d::Zero());
	reintegrate();
}

void InertialGraph::reintegrate()
{
	for (std::size_t i = 1; i < kfs_.size(); i++)
	{
		Kf& k = kfs_[i];
		const Vector6d b = bias(kfs_[i - 1]);
		if (!k.pim || !k.pim->bias_far(b, o_.reintegrate_accel, o_.reintegrate_gyro)) continue;
		auto pim = std::make_shared<ImuPreintegration>(*k.pim);
		pim->reintegrate(b);
		sm_.problem().remove_factor(k.imu);
		const Kf& prev = kfs_[i - 1];
		k.imu = add_factor(std::make_shared<ImuPreintegrationFactor>(pim), {prev.T, prev.v, prev.b, k.T, k.v, k.b});
		k.pim = pim;
		reintegrations++;
	}
}

void InertialGraph::marginalized(const smoother::TimedState&, const smoother::MarginalizationSummary&)
{
	kfs_.pop_front();
	kfs_.front().pim.reset();  // its IMU factor went into the prior
	kfs_.front().imu = -1;
}

void InertialGraph::set_first(const NavState& x, const Vector6d& b)
{
	Problem& p = sm_.problem();
	p.set_pose(kfs_.front().T, make_pose(x));
	p.set_value(kfs_.front().v, x.v.data());
	p.set_value(kfs_.front().b, b.data());
}

void InertialGraph::record_all(InertialTrajectory& out) const
{
	for (const Kf& k : kfs_) record(out, k, Matrix6d::Zero());
}

/** What the window and the batch start from: the initial state and the keyframes after it. */
struct InertialStart
{
	InertialInitialState init;
	std::vector<KeyframeData> keyframes;
};

/** Validates `o`; throws std::invalid_argument, naming `run`, when no keyframe follows the initial state. */
InertialStart inertial_start(const InertialInput& in, const InertialWindowOptions& o, const std::string& run)
{
	o.validate();
	InertialStart s{initial_inertial_state(in, o.measurements.prior), {}};
	s.keyframes = keyframes(in, o.measurements, s.init.t);
	if (s.keyframes.empty()) throw std::invalid_argument(run + ": no keyframe");
	return s;
}
}  // namespace

InertialWindowResult run_inertial_window(const InertialInput& in, const InertialWindowOptions& o)
{
	const auto [init, kd] = inertial_start(in, o, "inertial window");
	InertialGraph g(o, in, o.window_size);
	InertialWindowResult r;
	for (std::size_t i = 0; i < kd.size(); i++)
	{
		const auto start = SteadyClock::now();
		if (i == 0)
			g.add_first(init, kd[0]);
		else
			g.add_next(kd[i]);
		g.update(r.online, r.lagged);
		r.seconds_per_keyframe.push_back(seconds_since(start));
	}
	g.record_all(r.lagged);
	r.reintegrations = g.reintegrations;
	r.relative_factors = g.relative_factors;
	r.prior_factors = g.prior_factors;
	return r;
}

InertialTrajectory run_inertial_batch(const InertialInput& in, const InertialWindowOptions& o)
{
	const auto [init, kd] = inertial_start(in, o, "inertial batch");
	// Initial values from the filter (IMU dead reckoning over the whole run would be far off).
	const InertialTrajectory f = run_inertial_filter(in, o.measurements);
	if (f.t.size() != kd.size()) throw std::logic_error("inertial batch: filter and keyframe times differ");
	auto guess = [&f](std::size_t i) {
		NavState x;
		x.R = f.poses[i].getRotationMatrix().asEigen();
		x.p = Eigen::Vector3d(f.poses[i].x(), f.poses[i].y(), f.poses[i].z());
		x.v = f.velocities[i];
		return std::make_pair(x, f.biases[i]);
	};
	InertialGraph g(o, in, 0);
	g.add_first(init, kd[0]);
	g.set_first(guess(0).first, guess(0).second);
	for (std::size_t i = 1; i < kd.size(); i++) g.add_next(kd[i], guess(i));
	SolverOptions s = o.solver;
	s.max_iterations = 50;
	g.solve(s);
	if (g.reintegrate_moved() > 0) g.solve(s);
	InertialTrajectory out;
	g.record_all(out);
	return out;
}
}  // namespace swba::estimators
