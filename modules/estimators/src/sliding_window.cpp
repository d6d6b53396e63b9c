// The window: per step, the range-bearing graph grows by one pose and its readings, the fixed-lag
// smoother solves it, and once the window is full the landmark policy decides what leaves with the
// oldest pose. run_batch and run_full_history_causal are the unbounded siblings.
#include <swba/estimators/sliding_window.h>

#include "range_bearing_graph.h"
#include "young_readings.h"

#include <swba/core/manifold.h>

#include <algorithm>
#include <swba/core/timing.h>
#include <cmath>
#include <limits>
#include <optional>
#include <set>
#include <stdexcept>

namespace swba::estimators
{
/** The window as the smoother's client: per step, the range-bearing graph grows, then one
 * smoother update() calls back here to hold the gauge, read the solution and decide what leaves. */
struct SlidingWindowEstimator::Impl : smoother::SmootherClient
{
	detail::RangeBearingGraph graph;
	eval::Trajectory online, lagged;
	std::vector<PoseCovariance> online_cov, lagged_cov;
	/** The covariance of the pose leaving the window at lag W in this step's update() (from its solve,
	 * reported by left()). */
	std::optional<std::pair<VariableId, PoseCovariance>> leaving_cov;
	std::vector<StepSummary> summaries;
	std::optional<mrpt::poses::CPose3D> initial_left;  ///< the initial pose's estimate when it left the window
	bool finished = false;
	// The step being processed (set by process() around its update()).
	StepSummary* sum = nullptr;
	const std::map<VariableId, std::vector<double>>* before = nullptr;
	SteadyClock::time_point solve_start;
	std::set<VariableId> leaving_with_oldest;  ///< the landmarks leaving with the oldest pose
	detail::YoungReadingRule young;

	explicit Impl(const SlidingWindowOptions& o) : graph(o), young(o) {}

	smoother::FixedLagSmoother& smoother() { return graph.smoother(); }
	const smoother::FixedLagSmoother& smoother() const { return graph.smoother(); }
	const SlidingWindowOptions& opt() const { return graph.options(); }

	/** The pose that leaves the window at lag W at this step's update() (−1: none): once more than W
	 * poses are held, the oldest (the linear tail's, or the oldest re-linearised one without a tail). */
	VariableId leaving_pose() const
	{
		const int k = opt().relinearized_window();
		const std::size_t held = smoother().states().size();
		if (k == 0 || static_cast<int>(held) <= k) return -1;
		const auto linear = smoother().linear_states();
		if (static_cast<int>(held + linear.size()) <= opt().window_size) return -1;
		return linear.empty() ? smoother().states().front().var : linear.front().var;
	}

	smoother::PriorOnly prior_only(VariableId v) const override { return graph.prior_only(v); }

	bool hold(const smoother::UpdateSummary&) override
	{
		if (opt().gauge == GaugeMode::Free)
		{
			graph.hold_gauge(*before);
			return true;
		}
		return false;
	}

	void solved(const smoother::UpdateSummary& u) override
	{
		sum->prior_only_landmarks = u.prior_only_eliminated;
		sum->solve_seconds = seconds_since(solve_start) - u.covariance.seconds;
		sum->iterations = u.solver.iterations;
		sum->termination = u.solver.termination;
		sum->solver_message = u.solver.message;
		sum->initial_cost = u.solver.initial_cost;
		sum->final_cost = u.solver.final_cost;
		if (opt().covariances)
			keep_covariances(opt().gauge == GaugeMode::Free ? graph.covariances(covariance_request()) : u.covariance);
		if (graph.gate_on_entry()) graph.readmit_held(*sum);
		graph.reassociate(*sum);
		online.push_back(smoother().states().back().time, graph.pose(smoother().states().back().var));
	}

	/** The poses whose covariance a step reports: the newest (online) and the one leaving at lag W
	 * (lagged; in the linear tail, its covariance in the whole window's model, see
	 * FixedLagSmoother::update). Empty with covariances off. */
	CovarianceRequest covariance_request() const
	{
		CovarianceRequest r;
		if (!opt().covariances) return r;
		r.groups.push_back({smoother().states().back().var});
		if (const VariableId v = leaving_pose(); v >= 0) r.groups.push_back({v});
		return r;
	}

	void keep_covariances(const CovarianceResult& r)
	{
		sum->covariance_seconds = r.seconds;
		online_cov.push_back(graph.pose_covariance(r, 0));
		leaving_cov.reset();
		if (const VariableId v = leaving_pose(); v >= 0) leaving_cov.emplace(v, graph.pose_covariance(r, 1));
	}

	/** The landmark policy at the oldest pose (step o) leaving: landmarks anchored there are
	 * re-anchored or switched to world XYZ; with ConstantTime and Map, the landmarks no other window
	 * pose observes leave with it (returned). */
	std::set<VariableId> landmarks_leaving_with(std::size_t o)
	{
		std::set<VariableId> leaving;
		const std::size_t newest_step = graph.poses().size() - 1;
		for (const auto& [id, lm] : graph.landmarks())
		{
			std::size_t newest = o;
			for (const auto& ob : lm.obs)
				if (ob.pose_step != o) newest = std::max(newest, ob.pose_step);
			const bool seen_in_window = newest != o;
			if (opt().policy != LandmarkPolicy::Slam && !seen_in_window)
			{
				leaving.insert(lm.var);
				continue;
			}
			if (opt().landmarks == LandmarkParameterization::InverseDepth && !lm.world_xyz && lm.anchor_step == o)
			{
				if (smoother().in_prior(lm.var))
				{
					graph.convert_to_world_xyz(id);
					sum->landmarks_to_world++;
				}
				else
					graph.reanchor(id, seen_in_window ? newest : newest_step);
				sum->reanchored++;
			}
		}
		return leaving;
	}

	std::set<VariableId> leaving(const smoother::TimedState& oldest) override
	{
		const std::size_t o = graph.step_of(oldest.var);
		leaving_with_oldest = landmarks_leaving_with(o);
		const std::set<VariableId>& out = leaving_with_oldest;
		const std::set<FactorId> readings = graph.reading_factors_leaving(o, out);
		const std::vector<double> squares = graph.robust_squared_residuals(readings);
		sum->down_weighted += graph.count_beyond_scale(squares);
		if (young.testing()) young.add_tested(squares, graph.reading_dof());
		graph.expire_readings_at(o);
		if (opt().relinearized_window() < opt().window_size) graph.hold_tail_readings(o);
		if (opt().policy == LandmarkPolicy::Map) sum->landmarks_not_mapped += graph.keep_in_map(out);
		return out;
	}

	void marginalized(const smoother::TimedState&, const smoother::MarginalizationSummary& m) override
	{
		sum->unevaluable_factors += m.unevaluable_factors;
		graph.forget_observations(m.removed);
		for (VariableId v : leaving_with_oldest)
			if (graph.forget_landmark(v)) sum->marginalized_landmarks++;
	}

	/** Young landmarks' readings (SlidingWindowOptions::young_landmark_readings): the oldest
	 * re-linearised pose stays while a reading of it that is still a factor is one of a young landmark. */
	bool keep_relinearized(const smoother::TimedState& oldest) override
	{
		const std::size_t k = graph.step_of(oldest.var);
		std::vector<std::int32_t> ids;
		for (const auto& [id, lm] : graph.landmarks())
			for (const auto& ob : lm.obs)
				if (ob.pose_step == k) ids.push_back(id);
		return young.keeps(ids);
	}

	/** A pose leaves the window at lag W: the lagged output. */
	void left(const smoother::TimedState& s, const std::vector<double>& value) override
	{
		if (opt().relinearized_window() < opt().window_size) graph.release_tail_readings();
		const mrpt::poses::CPose3D pose = SE3Manifold::to_pose(value.data());
		lagged.push_back(s.time, pose);
		if (opt().covariances)
			lagged_cov.push_back(leaving_cov && leaving_cov->first == s.var
									 ? leaving_cov->second
									 : PoseCovariance::Constant(std::numeric_limits<double>::quiet_NaN()));
		if (s.var == graph.poses().front().var) initial_left = pose;
	}

	const StepSummary& process(const io::RawlogStep& step)
	{
		if (finished) throw std::logic_error("SlidingWindowEstimator: process() after finish()");
		const auto t0 = SteadyClock::now();
		StepSummary step_sum;
		step_sum.step = step.index;
		const auto snapshot = graph.gauge_snapshot();
		graph.add_step(step, step_sum);
		if (const std::size_t k = graph.poses().size() - 1; k < graph.assigned_ids().size())
			young.add_readings(graph.assigned_ids()[k]);
		sum = &step_sum;
		before = &snapshot;
		solve_start = SteadyClock::now();
		const CovarianceRequest request =
			opt().gauge == GaugeMode::Free ? CovarianceRequest{} : covariance_request();
		const smoother::UpdateSummary u = smoother().update(*this, request);
		sum = nullptr;
		before = nullptr;
		step_sum.marginalization_seconds = u.marginalization_seconds;
		if (const int k = opt().relinearized_window(); k > 0)
			step_sum.kept_relinearized = std::max(0, static_cast<int>(smoother().states().size()) - k);
		step_sum.window_poses = static_cast<int>(smoother().states().size() + smoother().linear_states().size());
		step_sum.landmarks = static_cast<int>(graph.landmarks().size());
		step_sum.prior_rank = smoother().prior().rank();
		step_sum.prior_variables = static_cast<int>(smoother().prior().variables().size());
		step_sum.seconds = seconds_since(t0);
		summaries.push_back(step_sum);
		return summaries.back();
	}

	void finish()
	{
		if (finished) return;
		finished = true;
		if (graph.poses().empty()) return;  // no step processed (model still undecided)
		graph.finish_counts();
		const VariableId initial = graph.poses().front().var;
		CovarianceRequest request;
		for (const smoother::LinearState& s : smoother().linear_states())
			if (s.var != initial)
			{
				lagged.push_back(s.time, SE3Manifold::to_pose(s.value.data()));
				request.groups.push_back({s.var});
			}
		for (const auto& s : smoother().states())
			if (s.var != initial)
			{
				lagged.push_back(s.time, graph.pose(s.var));
				request.groups.push_back({s.var});
			}
		if (!opt().covariances) return;
		const CovarianceResult r = graph.covariances(request);
		for (std::size_t g = 0; g < request.groups.size(); g++) lagged_cov.push_back(graph.pose_covariance(r, g));
	}
};

SlidingWindowEstimator::SlidingWindowEstimator(const SlidingWindowOptions& options)
	: impl_(std::make_unique<Impl>(options))
{
}
SlidingWindowEstimator::~SlidingWindowEstimator() = default;

const StepSummary& SlidingWindowEstimator::process(const io::RawlogStep& step) { return impl_->process(step); }
void SlidingWindowEstimator::finish() { impl_->finish(); }
mrpt::poses::CPose3D SlidingWindowEstimator::current_pose() const
{
	const auto& sm = impl_->graph.smoother();
	if (sm.states().empty()) return mrpt::poses::CPose3D();  // before the first step: the origin
	return impl_->graph.pose(sm.states().back().var);
}
std::vector<std::pair<double, mrpt::poses::CPose3D>> SlidingWindowEstimator::window_poses() const
{
	const auto& sm = impl_->graph.smoother();
	std::vector<std::pair<double, mrpt::poses::CPose3D>> out;
	if (sm.states().empty()) out.emplace_back(0.0, mrpt::poses::CPose3D());  // before the first step
	for (const auto& s : sm.linear_states()) out.emplace_back(s.time, SE3Manifold::to_pose(s.value.data()));
	for (const auto& s : sm.states()) out.emplace_back(s.time, impl_->graph.pose(s.var));
	return out;
}
std::map<std::int32_t, Eigen::Vector3d> SlidingWindowEstimator::landmarks() const
{
	return impl_->graph.landmark_positions();
}
mrpt::poses::CPose3D SlidingWindowEstimator::initial_pose() const
{
	if (impl_->initial_left) return *impl_->initial_left;
	if (impl_->graph.poses().empty()) return mrpt::poses::CPose3D();  // before the first step: the origin
	const VariableId initial = impl_->graph.poses().front().var;
	for (const auto& s : impl_->graph.smoother().linear_states())
		if (s.var == initial) return SE3Manifold::to_pose(s.value.data());
	return impl_->graph.pose(initial);
}
const eval::Trajectory& SlidingWindowEstimator::online_trajectory() const { return impl_->online; }
const eval::Trajectory& SlidingWindowEstimator::lagged_trajectory() const { return impl_->lagged; }
const std::vector<PoseCovariance>& SlidingWindowEstimator::online_covariances() const { return impl_->online_cov; }
const std::vector<PoseCovariance>& SlidingWindowEstimator::lagged_covariances() const { return impl_->lagged_cov; }
std::map<std::int32_t, LandmarkEstimate> SlidingWindowEstimator::landmark_estimates()
{
	return impl_->graph.landmark_estimates(nullptr);
}
const std::vector<StepSummary>& SlidingWindowEstimator::step_summaries() const { return impl_->summaries; }

std::vector<std::vector<std::int32_t>> SlidingWindowEstimator::assigned_ids() const
{
	// The graph's are by pose (pose k + 1 is step k's).
	const auto& by_pose = impl_->graph.assigned_ids();
	std::vector<std::vector<std::int32_t>> out(impl_->summaries.size());
	for (std::size_t k = 0; k < out.size() && k + 1 < by_pose.size(); k++) out[k] = by_pose[k + 1];
	return out;
}
ReadingCounts SlidingWindowEstimator::reading_counts() const
{
	ReadingCounts c = impl_->graph.counts();
	for (const auto& s : impl_->summaries)
	{
		c.down_weighted += static_cast<std::size_t>(s.down_weighted);
		if (s.kept_relinearized > 0) c.young_held_steps++;
	}
	// The readings still in the window (never marginalised: all of them at W = inf) count at the current
	// estimate, as the batch's count at its solution.
	std::set<FactorId> in_window;
	for (const auto& [id, lm] : impl_->graph.landmarks())
		for (const auto& ob : lm.obs) in_window.insert(ob.factor);
	c.down_weighted += static_cast<std::size_t>(impl_->graph.count_down_weighted(in_window));
	return c;
}
const SlidingWindowOptions& SlidingWindowEstimator::options() const { return impl_->graph.options(); }

const smoother::FixedLagSmoother& SlidingWindowEstimator::smoother() const { return impl_->graph.smoother(); }

const smoother::MarginalPrior& SlidingWindowEstimator::marginal_prior() const
{
	return impl_->graph.smoother().prior();
}

Eigen::MatrixXd SlidingWindowEstimator::prior_information() const
{
	const Eigen::MatrixXd& J = impl_->graph.smoother().prior().J();
	return J.transpose() * J;
}

Eigen::MatrixXd SlidingWindowEstimator::prior_gauge_directions() const
{
	const auto& graph = impl_->graph;
	const auto& sm = graph.smoother();
	std::vector<Eigen::MatrixXd> blocks;
	Eigen::Index n = 0;
	for (VariableId v : sm.prior().variables())
	{
		blocks.push_back(graph.gauge_directions(v, sm.linearization_point(v)));
		n += blocks.back().rows();
	}
	Eigen::MatrixXd N(n, 6);
	Eigen::Index off = 0;
	for (const auto& B : blocks)
	{
		N.middleRows(off, B.rows()) = B;
		off += B.rows();
	}
	return N;
}

// ----------------------------------------------------------------------------------------------
namespace
{
/** The batch's covariances at its solution: every pose after the initial one, then the landmarks. */
void batch_covariances(detail::RangeBearingGraph& graph, BatchResult& r)
{
	CovarianceRequest request;
	for (std::size_t k = 1; k < graph.poses().size(); k++) request.groups.push_back({graph.poses()[k].var});
	const CovarianceResult c = graph.covariances(request);
	for (std::size_t g = 0; g < request.groups.size(); g++)
		r.covariances.push_back(graph.pose_covariance(c, g));
	double landmark_seconds = 0;
	r.landmarks = graph.landmark_estimates(&landmark_seconds);
	r.covariance_seconds = c.seconds + landmark_seconds;
}
}  // namespace

BatchResult run_batch(const io::Rawlog& rawlog, const SlidingWindowOptions& options, int max_iterations,
					  const eval::Trajectory* start)
{
	const auto t0 = SteadyClock::now();
	SlidingWindowOptions o = options;
	o.window_size = 0;
	detail::RangeBearingGraph graph(o);
	graph.set_gate_on_entry(false);  // dead reckoning over the whole run is no prediction to gate against
	if (start)
	{
		std::map<double, mrpt::poses::CPose3D> guesses;
		for (std::size_t i = 0; i < start->size(); i++) guesses.emplace(start->stamps[i], start->poses[i]);
		graph.set_pose_guesses(std::move(guesses));
	}
	StepSummary unused;
	for (const auto& s : rawlog.steps)
	{
		try
		{
			graph.add_step(s, unused);
		}
		catch (const std::invalid_argument& e)
		{
			throw StepError(s.index, e.what());
		}
	}
	SolverOptions so = o.solver;
	so.max_iterations = max_iterations;
	so.function_tolerance = std::min(so.function_tolerance, 1e-12);
	BatchResult r;
	if (o.gate_readings)
	{
		// The first solve is robust (Cauchy at the gate's radius), so that the gate's first test sees an
		// estimate the outliers have not dragged (least squares, or Huber's bounded but non-vanishing
		// influence, left enough bias to gate good readings with 5 % outliers); then the options' own loss.
		graph.set_reading_loss(make_loss(RobustLoss::Cauchy, std::sqrt(o.gate_threshold(graph.reading_dof()))));
		swba::solve(graph.smoother().problem(), so);
		graph.set_reading_loss(o.reading_loss(graph.reading_dof()));
		graph.regate_all();
		r.rounds++;
	}
	r.summary = swba::solve(graph.smoother().problem(), so);
	constexpr int kMaxRounds = 6;
	while (o.gate_readings && r.rounds < kMaxRounds && graph.regate_all())
	{
		r.summary = swba::solve(graph.smoother().problem(), so);
		r.rounds++;
	}
	r.counts = graph.counts();
	std::set<FactorId> readings;
	for (const auto& [id, lm] : graph.landmarks())
		for (const auto& ob : lm.obs) readings.insert(ob.factor);
	r.counts.down_weighted = static_cast<std::size_t>(graph.count_down_weighted(readings));
	r.initial_pose = graph.pose(graph.poses().front().var);
	for (std::size_t k = 1; k < graph.poses().size(); k++)
		r.trajectory.push_back(graph.poses()[k].time, graph.pose(graph.poses()[k].var));
	if (o.covariances && r.summary.is_solution_usable()) batch_covariances(graph, r);
	r.seconds = seconds_since(t0);
	return r;
}

eval::Trajectory run_full_history_causal(const io::Rawlog& rawlog, const SlidingWindowOptions& options,
										 ReadingCounts* counts, mrpt::poses::CPose3D* initial_pose)
{
	SlidingWindowOptions o = options;
	o.window_size = 0;
	o.covariances = false;  // the causal row reports none
	SlidingWindowEstimator est(o);
	for (const auto& s : rawlog.steps)
	{
		try
		{
			est.process(s);
		}
		catch (const std::invalid_argument& e)
		{
			throw StepError(s.index, e.what());
		}
	}
	est.finish();
	if (counts) *counts = est.reading_counts();
	if (initial_pose) *initial_pose = est.initial_pose();
	return est.online_trajectory();
}
}  // namespace swba::estimators
