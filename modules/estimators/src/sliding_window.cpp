#include <swba/estimators/sliding_window.h>

#include <swba/factors/first_estimate.h>
#include <swba/factors/between_pose.h>
#include <swba/factors/linear_prior.h>
#include <swba/factors/pose_prior.h>
#include <swba/factors/range_bearing.h>
#include <swba/linear/marginal.h>
#include <swba/nonlinear/linearization.h>

#include "prior_only_elimination.h"

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <deque>
#include <set>
#include <stdexcept>

namespace swba::estimators
{
// ----------------------------------------------------------------------------------------------
// Option parsing
LandmarkParameterization parse_landmark_parameterization(const std::string& s)
{
	if (s == "inverse-depth") return LandmarkParameterization::InverseDepth;
	if (s == "xyz") return LandmarkParameterization::Xyz;
	throw std::invalid_argument("unknown landmark parameterisation '" + s + "' (expected inverse-depth or xyz)");
}
LandmarkPolicy parse_landmark_policy(const std::string& s)
{
	if (s == "slam") return LandmarkPolicy::Slam;
	if (s == "constant-time") return LandmarkPolicy::ConstantTime;
	throw std::invalid_argument("unknown landmark policy '" + s + "' (expected slam or constant-time)");
}
std::string to_string(LandmarkParameterization p) { return p == LandmarkParameterization::Xyz ? "xyz" : "inverse-depth"; }
std::string to_string(LandmarkPolicy p) { return p == LandmarkPolicy::Slam ? "slam" : "constant-time"; }
SolverOptions SlidingWindowOptions::default_solver_options()
{
	SolverOptions s;
	s.max_iterations = 10;
	// From a warm start the window's cost settles within 2–3 iterations; 1e-9 added iterations that each
	// moved the cost by < 1e-7 relative (≈ 7.3 instead of ≈ 4.5 per step on kf-slam_6D_demo, same APE to
	// 5 digits). 1e-6 saves one more iteration but moved the lagged APE of the 5000-step run by up to
	// 0.7 %; 1e-7 keeps both runs' APE within 0.1 % (doc/run.md, "Benchmark").
	s.function_tolerance = 1e-7;
	return s;
}

void SlidingWindowOptions::validate() const
{
	if (window_size != 0 && window_size < 2)
		throw std::invalid_argument("window size must be >= 2 (or 0 for unbounded), got " + std::to_string(window_size));
	if (!(gauge_prior_weight > 0)) throw std::invalid_argument("gauge prior weight must be > 0");
	if (!(marginalization_threshold >= 0) || !(marginalization_threshold < 1))
		throw std::invalid_argument("marginalisation threshold must be in [0, 1)");
	for (double s : {sensor_std_range, sensor_std_yaw, sensor_std_pitch})
		if (!std::isfinite(s)) throw std::invalid_argument("sensor noise must be finite");
	std::string why;
	if (!solver.is_valid(&why)) throw std::invalid_argument("solver options: " + why);
}

// ----------------------------------------------------------------------------------------------
namespace
{
using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

struct Observation
{
	std::size_t pose_step;  // index into poses_ (0 = initial pose)
	RangeBearingMeasurement z;
	Eigen::Vector3d sigma;
	FactorId factor = -1;
};

struct Landmark
{
	std::int32_t id;
	VariableId var;
	std::size_t anchor_step = 0;  // inverse depth only
	/** Inverse-depth mode: the landmark was in the marginal prior when its anchor left the window, so it
	 * was switched to world XYZ (a parameterisation no later marginalisation has to change). */
	bool world_xyz = false;
	std::vector<Observation> obs;  // observations whose factors are still in the problem
};

struct PoseRecord
{
	double time;
	VariableId var;
	mrpt::poses::CPose3D sensor;  // sensor pose on the robot at this step
	bool in_window;
};

struct Prior
{
	FactorId factor = -1;
	std::vector<VariableId> vars;
	Eigen::MatrixXd J;
	Eigen::VectorXd e;
	std::vector<std::vector<double>> x_lin;
	/** Its information H = JᵀJ and b = −Jᵀe (the Schur complement it came from) while `has_information`;
	 * a change of variables in J refreshes the columns it rewrote (refresh_information), a new zero column
	 * extends them with zeros. */
	Eigen::MatrixXd H;
	Eigen::VectorXd b;
	bool has_information = false;
};
}  // namespace

struct SlidingWindowEstimator::Impl
{
	SlidingWindowOptions opt;
	bool solve_each_step = true;
	Problem problem;
	std::shared_ptr<FirstEstimateRegistry> fej = std::make_shared<FirstEstimateRegistry>();
	std::vector<PoseRecord> poses;      // every pose ever created, by step (0 = initial)
	std::deque<std::size_t> window;     // pose steps in the window, oldest first
	std::map<std::int32_t, Landmark> landmarks;
	std::map<VariableId, std::int32_t> landmark_of_var;
	Prior prior;
	eval::Trajectory online, lagged;
	std::vector<StepSummary> summaries;
	mrpt::poses::CPose3D last_sensor;
	bool finished = false;

	explicit Impl(const SlidingWindowOptions& o) : opt(o)
	{
		opt.validate();
		const VariableId v0 = problem.add_pose(mrpt::poses::CPose3D());
		poses.push_back({0.0, v0, mrpt::poses::CPose3D(), true});
		window.push_back(0);
		if (opt.gauge == GaugeMode::Fixed)
			problem.set_constant(v0);
		else if (opt.gauge == GaugeMode::Prior)
		{
			auto f = std::make_shared<PosePriorFactor>(mrpt::poses::CPose3D());
			f->set_information(opt.gauge_prior_weight * Eigen::MatrixXd::Identity(6, 6));
			add_factor(f, {v0});
		}
	}

	FactorId add_factor(std::shared_ptr<const Factor> f, std::vector<VariableId> vars)
	{
		if (opt.first_estimate_jacobians)
			f = std::make_shared<FirstEstimateFactor>(std::move(f), vars, fej);
		return problem.add_factor(std::move(f), std::move(vars));
	}

	void freeze(VariableId v)
	{
		if (!opt.first_estimate_jacobians) return;
		if (fej->count(v) || problem.is_constant(v)) return;
		(*fej)[v] = problem.variable(v).value;
	}

	bool is_world_xyz_landmark(VariableId v) const
	{
		auto it = landmark_of_var.find(v);
		return it != landmark_of_var.end() && landmarks.at(it->second).world_xyz;
	}

	const double* fej_or_current(VariableId v) const
	{
		auto it = fej->find(v);
		return it != fej->end() ? it->second.data() : problem.value(v);
	}

	Eigen::Vector3d sigma_for(const io::RawlogStep& step) const
	{
		Eigen::Vector3d s(opt.sensor_std_range > 0 ? opt.sensor_std_range : step.sensor_std_range,
						  opt.sensor_std_yaw > 0 ? opt.sensor_std_yaw : step.sensor_std_yaw,
						  opt.sensor_std_pitch > 0 ? opt.sensor_std_pitch : step.sensor_std_pitch);
		for (int i = 0; i < 3; i++)
			if (!(s[i] > 0))
				throw std::invalid_argument("step " + std::to_string(step.index) +
											": sensor noise is not positive (set sensor_std_* in the options)");
		return s;
	}

	/** Builds the factor of observation `o` of landmark `lm` (given its current anchor). */
	FactorId add_observation_factor(const Landmark& lm, const Observation& o)
	{
		std::shared_ptr<Factor> f;
		std::vector<VariableId> vars;
		const auto& P = poses[o.pose_step];
		if (opt.landmarks == LandmarkParameterization::Xyz || lm.world_xyz)
		{
			f = std::make_shared<RangeBearingXyzFactor>(o.z, P.sensor);
			vars = {P.var, lm.var};
		}
		else if (o.pose_step == lm.anchor_step)
		{
			f = std::make_shared<RangeBearingInverseDepthAnchorFactor>(o.z);
			vars = {lm.var};
		}
		else
		{
			f = std::make_shared<RangeBearingInverseDepthFactor>(o.z, P.sensor, poses[lm.anchor_step].sensor);
			vars = {poses[lm.anchor_step].var, P.var, lm.var};
		}
		f->set_information(o.sigma.cwiseInverse().cwiseAbs2().asDiagonal().toDenseMatrix());
		return add_factor(f, vars);
	}

	void set_prior(Prior p)
	{
		if (prior.factor >= 0) problem.remove_factor(prior.factor);
		prior = std::move(p);
		prior.factor = -1;
		if (prior.vars.empty() || prior.J.rows() == 0)
		{
			prior = Prior();
			return;
		}
		std::vector<std::shared_ptr<const Manifold>> man;
		for (VariableId v : prior.vars) man.push_back(problem.variable(v).manifold);
		auto f = std::make_shared<LinearPriorFactor>(prior.J, prior.e, prior.x_lin, man);
		prior.factor = problem.add_factor(f, prior.vars);
	}

	int prior_index(VariableId v) const
	{
		auto it = std::find(prior.vars.begin(), prior.vars.end(), v);
		return it == prior.vars.end() ? -1 : static_cast<int>(it - prior.vars.begin());
	}

	int prior_offset(int idx) const
	{
		int off = 0;
		for (int i = 0; i < idx; i++) off += problem.variable(prior.vars[i]).manifold->tangent_size();
		return off;
	}

	/** After a change of variables rewrote J's columns [c0, c0 + n): recomputes the same rows/columns of
	 * the stored information H = JᵀJ and entries of b = −Jᵀe (O(rank·cols·n), not a new JᵀJ). */
	void refresh_information(int c0, int n)
	{
		if (!prior.has_information) return;
		const Eigen::MatrixXd cols = prior.J.transpose() * prior.J.middleCols(c0, n);
		prior.H.middleCols(c0, n) = cols;
		prior.H.middleRows(c0, n) = cols.transpose();
		prior.b.segment(c0, n) = -(prior.J.middleCols(c0, n).transpose() * prior.e);
	}

	/** Adds variable v to the prior with zero columns (x_lin = current value); returns its index. */
	int ensure_in_prior(VariableId v)
	{
		int idx = prior_index(v);
		if (idx >= 0) return idx;
		const int n = problem.variable(v).manifold->tangent_size();
		Eigen::MatrixXd J(prior.J.rows(), prior.J.cols() + n);
		J << prior.J, Eigen::MatrixXd::Zero(prior.J.rows(), n);
		if (prior.has_information)
		{
			// The new columns of J are zero: so are the new rows and columns of H and entries of b.
			const Eigen::Index m = prior.H.rows();
			prior.H.conservativeResize(m + n, m + n);
			prior.H.rightCols(n).setZero();
			prior.H.bottomRows(n).setZero();
			prior.b.conservativeResize(m + n);
			prior.b.tail(n).setZero();
		}
		prior.J = J;
		prior.vars.push_back(v);
		prior.x_lin.push_back(problem.variable(v).value);
		return static_cast<int>(prior.vars.size()) - 1;
	}

	/** Moves landmark `lm` onto variable `v` (its new parameterisation, already set in `lm`): removes
	 * its observation factors and old variable, and rebuilds the factors on `v` (an exact rewrite). */
	void replace_landmark_variable(Landmark& lm, VariableId v)
	{
		for (auto& o : lm.obs) problem.remove_factor(o.factor);
		fej->erase(lm.var);
		landmark_of_var.erase(lm.var);
		problem.remove_variable(lm.var);
		lm.var = v;
		landmark_of_var[v] = lm.id;
		for (auto& o : lm.obs) o.factor = add_observation_factor(lm, o);
	}

	/** Switches inverse-depth landmark `lm`, which is in the marginal prior and whose anchor a is about
	 * to be marginalised, to world XYZ p: an exact rewrite of its factors, and a first-order change of
	 * variables λ = g(T_a, p) (p seen from a's sensor, as inverse depth) in the prior, at the first
	 * estimates. T_a is marginalised right after, so the prior never depends on a re-anchoring again:
	 * a landmark in the prior changes parameterisation once, not every time its anchor leaves. */
	void convert_to_world_xyz(Landmark& lm)
	{
		const std::size_t a = lm.anchor_step;
		const VariableId va = poses[a].var, vl = lm.var;
		const Eigen::Vector3d lam = Eigen::Map<const Eigen::Vector3d>(problem.value(vl));
		const Eigen::Vector3d p = inverse_depth_to_world(problem.value(va), poses[a].sensor, lam);
		const VariableId vp = problem.add_variable(p, euclidean_manifold(3), Group::Eliminable);

		const int pidx = prior_index(vl);
		freeze(va);
		const int ia = ensure_in_prior(va);
		const Eigen::Vector3d lam_lin = Eigen::Map<const Eigen::Vector3d>(prior.x_lin[pidx].data());
		const Eigen::Vector3d p_lin = inverse_depth_to_world(prior.x_lin[ia].data(), poses[a].sensor, lam_lin);
		// Jacobians at the first estimates (or the current values without FEJ).
		const double* Ta_f = fej_or_current(va);
		const Eigen::Vector3d lam_f = Eigen::Map<const Eigen::Vector3d>(fej_or_current(vl));
		const Eigen::Vector3d p_f = inverse_depth_to_world(Ta_f, poses[a].sensor, lam_f);
		RangeBearingXyzFactor h_of({1.0, 0.0, 0.0}, poses[a].sensor);  // h = [range, yaw, pitch] − [1, 0, 0]
		Eigen::Matrix<double, 3, 6, Eigen::RowMajor> Ha;
		Eigen::Matrix<double, 3, 3, Eigen::RowMajor> Hp;
		Eigen::Vector3d r;
		const double* xs[2] = {Ta_f, p_f.data()};
		double* js[2] = {Ha.data(), Hp.data()};
		if (!h_of.evaluate(xs, r.data(), js))
			throw std::runtime_error("landmark " + std::to_string(lm.id) + ": range-bearing model undefined at its anchor");
		const double range = r[0] + 1.0;
		Eigen::Matrix3d D;  // ∂λ/∂h for λ = [yaw, pitch, 1/range]
		D << 0, 1, 0, 0, 0, 1, -1.0 / (range * range), 0, 0;
		const int ol = prior_offset(pidx), oa = prior_offset(ia);
		const Eigen::MatrixXd Jl = prior.J.middleCols(ol, 3);
		prior.J.middleCols(oa, 6) += Jl * D * Ha;
		prior.J.middleCols(ol, 3) = Jl * D * Hp;
		refresh_information(oa, 6);
		refresh_information(ol, 3);
		prior.vars[pidx] = vp;
		prior.x_lin[pidx] = std::vector<double>(p_lin.data(), p_lin.data() + 3);
		if (opt.first_estimate_jacobians) (*fej)[vp] = std::vector<double>(p_f.data(), p_f.data() + 3);
		set_prior(prior);

		lm.world_xyz = true;
		replace_landmark_variable(lm, vp);
	}

	/** Re-anchors inverse-depth landmark `lm` to pose step `b`: an exact rewrite of its factors, and
	 * a first-order change of variables λ = g(T_a, T_b, λ') in the prior if λ is in it. */
	void reanchor(Landmark& lm, std::size_t b)
	{
		const std::size_t a = lm.anchor_step;
		const VariableId va = poses[a].var, vb = poses[b].var, vl = lm.var;
		const Eigen::Vector3d lam = Eigen::Map<const Eigen::Vector3d>(problem.value(vl));
		Eigen::Vector3d lam_new;
		try
		{
			lam_new = reanchor_inverse_depth(problem.value(va), poses[a].sensor, problem.value(vb), poses[b].sensor, lam);
		}
		catch (const std::invalid_argument& e)
		{
			throw std::runtime_error("re-anchoring landmark " + std::to_string(lm.id) + " at time " +
									 std::to_string(poses[b].time) + ": " + e.what() + " (the estimate diverged)");
		}
		const VariableId vl2 = problem.add_variable(lam_new, euclidean_manifold(3), Group::Eliminable);

		const int pidx = prior.factor >= 0 ? prior_index(vl) : -1;
		if (pidx >= 0)
		{
			// λ = g(λ', T_b, T_a): λ is the new landmark seen from the old anchor's sensor, in inverse depth.
			freeze(va);
			freeze(vb);
			const int ia = ensure_in_prior(va), ib = ensure_in_prior(vb);
			const double* Ta_lin = prior.x_lin[ia].data();
			const double* Tb_lin = prior.x_lin[ib].data();
			const Eigen::Vector3d lam_lin = Eigen::Map<const Eigen::Vector3d>(prior.x_lin[pidx].data());
			const Eigen::Vector3d lam2_lin =
				reanchor_inverse_depth(Ta_lin, poses[a].sensor, Tb_lin, poses[b].sensor, lam_lin);
			// Jacobians at the first estimates (or the current values without FEJ).
			const double* Ta_f = fej_or_current(va);
			const double* Tb_f = fej_or_current(vb);
			const Eigen::Vector3d lam_f = Eigen::Map<const Eigen::Vector3d>(fej_or_current(vl));
			const Eigen::Vector3d lam2_f =
				reanchor_inverse_depth(Ta_f, poses[a].sensor, Tb_f, poses[b].sensor, lam_f);
			RangeBearingInverseDepthFactor h_of({1.0, 0.0, 0.0}, poses[a].sensor, poses[b].sensor);
			Eigen::Matrix<double, 3, 6, Eigen::RowMajor> Hb, Ha;
			Eigen::Matrix<double, 3, 3, Eigen::RowMajor> Hl;
			Eigen::Vector3d r;
			const double* xs[3] = {Tb_f, Ta_f, lam2_f.data()};
			double* js[3] = {Hb.data(), Ha.data(), Hl.data()};
			if (!h_of.evaluate(xs, r.data(), js))
				throw std::runtime_error("re-anchoring landmark " + std::to_string(lm.id) + ": model undefined");
			const double range = r[0] + 1.0;
			Eigen::Matrix3d D;  // ∂λ/∂h for λ = [yaw, pitch, 1/range]
			D << 0, 1, 0, 0, 0, 1, -1.0 / (range * range), 0, 0;
			const int ol = prior_offset(pidx), oa = prior_offset(ia), ob = prior_offset(ib);
			const Eigen::MatrixXd Jl = prior.J.middleCols(ol, 3);
			prior.J.middleCols(oa, 6) += Jl * D * Ha;
			prior.J.middleCols(ob, 6) += Jl * D * Hb;
			prior.J.middleCols(ol, 3) = Jl * D * Hl;
			refresh_information(oa, 6);
			refresh_information(ob, 6);
			refresh_information(ol, 3);
			prior.vars[pidx] = vl2;
			prior.x_lin[pidx] = std::vector<double>(lam2_lin.data(), lam2_lin.data() + 3);
			if (opt.first_estimate_jacobians) (*fej)[vl2] = std::vector<double>(lam2_f.data(), lam2_f.data() + 3);
			set_prior(prior);
		}
		lm.anchor_step = b;
		replace_landmark_variable(lm, vl2);
	}

	void add_step(const io::RawlogStep& step, StepSummary& sum)
	{
		if (!step.has_odometry)
			throw std::invalid_argument("step " + std::to_string(step.index) + " has no odometry");
		const std::size_t prev = window.back();
		const VariableId vprev = poses[prev].var;
		const mrpt::poses::CPose3D pose_new = problem.pose(vprev) + step.odometry.mean;
		const VariableId vnew = problem.add_pose(pose_new);
		if (step.has_observation) last_sensor = step.sensor_pose;
		poses.push_back({step.time(), vnew, step.has_observation ? step.sensor_pose : last_sensor, true});
		const std::size_t k = poses.size() - 1;
		window.push_back(k);
		auto odo = std::make_shared<BetweenPoseFactor>(step.odometry.mean);
		odo->set_information(io::odometry_information(step.odometry, opt.odometry));
		add_factor(odo, {vprev, vnew});
		if (step.readings.empty()) return;
		const Eigen::Vector3d sigma = sigma_for(step);
		for (const auto& rd : step.readings)
		{
			Observation o{k, {rd.range, rd.yaw, rd.pitch}, sigma, -1};
			auto it = landmarks.find(rd.landmark_id);
			if (it == landmarks.end())
			{
				Landmark lm;
				lm.id = rd.landmark_id;
				lm.anchor_step = k;
				Eigen::Vector3d x0;
				const Eigen::Vector3d lam = inverse_depth_from_measurement(o.z);
				if (opt.landmarks == LandmarkParameterization::Xyz)
					x0 = inverse_depth_to_world(problem.value(vnew), poses[k].sensor, lam);
				else
					x0 = lam;
				lm.var = problem.add_variable(x0, euclidean_manifold(3), Group::Eliminable);
				landmark_of_var[lm.var] = lm.id;
				it = landmarks.emplace(lm.id, std::move(lm)).first;
			}
			o.factor = add_observation_factor(it->second, o);
			it->second.obs.push_back(o);
			sum.readings++;
		}
	}

	void marginalize_oldest(StepSummary& sum)
	{
		const std::size_t o = window.front();
		const VariableId vo = poses[o].var;
		std::set<VariableId> marg{vo};
		// 1. Landmarks anchored at the leaving pose: re-anchor, or marginalise (constant-time, unseen).
		for (auto& [id, lm] : landmarks)
		{
			std::size_t newest = o;
			for (const auto& ob : lm.obs)
				if (ob.pose_step != o) newest = std::max(newest, ob.pose_step);
			const bool seen_in_window = newest != o;
			if (opt.policy == LandmarkPolicy::ConstantTime && !seen_in_window)
			{
				marg.insert(lm.var);
				continue;
			}
			if (opt.landmarks == LandmarkParameterization::InverseDepth && !lm.world_xyz && lm.anchor_step == o)
			{
				if (prior.factor >= 0 && prior_index(lm.var) >= 0)
				{
					convert_to_world_xyz(lm);
					sum.landmarks_to_world++;
				}
				else
					reanchor(lm, seen_in_window ? newest : window.back());
				sum.reanchored++;
			}
		}
		// 2. Factors touching the marginalised variables, and their other variables (kept).
		std::set<FactorId> fm;
		for (VariableId v : marg)
			for (FactorId f : problem.variable(v).factors) fm.insert(f);
		std::vector<VariableId> keep, margv;
		std::set<VariableId> seen;
		for (FactorId f : fm)
			for (VariableId v : problem.factor(f).variables)
				if (!marg.count(v) && !problem.is_constant(v) && seen.insert(v).second) keep.push_back(v);
		for (VariableId v : marg)
			if (!problem.is_constant(v)) margv.push_back(v);
		for (VariableId v : keep) freeze(v);
		// 3. Dense linearisation (FEJ through the decorators) and Schur complement.
		std::vector<VariableId> order = keep;
		order.insert(order.end(), margv.begin(), margv.end());
		const std::vector<FactorId> flist(fm.begin(), fm.end());
		// The old prior enters from its known information (no JᵀJ over its whole state per step).
		detail::KnownPrior known;
		if (prior.factor >= 0 && prior.has_information)
			known = {prior.factor, &prior.vars, &prior.x_lin, &prior.H, &prior.b};
		const detail::DenseNormalSystem sys = detail::dense_normal_system(problem, order, flist, known);
		const int nk = sys.offsets[keep.size()];
		const MarginalizationResult m = marginalize_leading(sys.H, sys.b, nk, opt.marginalization_threshold);
		// 4. Replace those factors and variables by the new prior.
		Prior p;
		p.J = m.J;
		p.e = m.e;
		p.H = m.H;
		p.b = m.b;
		p.has_information = true;
		p.vars = keep;
		for (VariableId v : keep) p.x_lin.push_back(problem.variable(v).value);
		if (prior.factor >= 0 && fm.count(prior.factor)) prior.factor = -1;  // removed below
		for (FactorId f : fm) problem.remove_factor(f);
		for (auto& [id, lm] : landmarks)
			lm.obs.erase(std::remove_if(lm.obs.begin(), lm.obs.end(),
										[&](const Observation& ob) { return fm.count(ob.factor) > 0; }),
						 lm.obs.end());
		lagged.push_back(poses[o].time, problem.pose(vo));
		for (VariableId v : marg)
		{
			fej->erase(v);
			auto it = landmark_of_var.find(v);
			if (it != landmark_of_var.end())
			{
				landmarks.erase(it->second);
				landmark_of_var.erase(it);
				sum.marginalized_landmarks++;
			}
			problem.remove_variable(v);
		}
		poses[o].in_window = false;
		window.pop_front();
		if (m.rank > 0)
			set_prior(std::move(p));
		else
			prior = Prior();
	}

	const StepSummary& process(const io::RawlogStep& step)
	{
		if (finished) throw std::logic_error("SlidingWindowEstimator: process() after finish()");
		const auto t0 = Clock::now();
		StepSummary sum;
		sum.step = step.index;
		add_step(step, sum);
		if (solve_each_step)
		{
			const auto ts = Clock::now();
			detail::PriorOnlyElimination elim;
			const auto is_landmark = [&](VariableId v) { return landmark_of_var.count(v) > 0; };
			bool reduced = false;
			if (opt.eliminate_prior_only_landmarks && prior.factor >= 0)
				reduced = prior.has_information
					? elim.begin(problem, prior.factor, prior.vars, prior.H, prior.b, prior.x_lin,
								 opt.marginalization_threshold, is_landmark, true)
					: elim.begin(problem, prior.factor, prior.vars, prior.J, prior.e, prior.x_lin,
								 opt.marginalization_threshold, is_landmark);
			if (reduced) prior.factor = -1;  // removed by begin(), re-added below
			const Summary s = solve(problem, opt.solver);
			if (reduced)
			{
				sum.prior_only_landmarks = elim.num_eliminated();
				elim.end(problem);
				set_prior(prior);
			}
			sum.solve_seconds = seconds_since(ts);
			sum.iterations = s.iterations;
			sum.initial_cost = s.initial_cost;
			sum.final_cost = s.final_cost;
		}
		online.push_back(step.time(), problem.pose(poses[window.back()].var));
		if (opt.window_size > 0 && static_cast<int>(window.size()) > opt.window_size)
		{
			const auto tm = Clock::now();
			marginalize_oldest(sum);
			sum.marginalization_seconds = seconds_since(tm);
		}
		sum.window_poses = static_cast<int>(window.size());
		sum.landmarks = static_cast<int>(landmarks.size());
		sum.prior_rank = static_cast<int>(prior.J.rows());
		sum.prior_variables = static_cast<int>(prior.vars.size());
		sum.seconds = seconds_since(t0);
		summaries.push_back(sum);
		return summaries.back();
	}

	void finish()
	{
		if (finished) return;
		finished = true;
		for (std::size_t s : window)
			if (s > 0) lagged.push_back(poses[s].time, problem.pose(poses[s].var));
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
	return impl_->problem.pose(impl_->poses[impl_->window.back()].var);
}
std::vector<std::pair<double, mrpt::poses::CPose3D>> SlidingWindowEstimator::window_poses() const
{
	std::vector<std::pair<double, mrpt::poses::CPose3D>> out;
	for (std::size_t s : impl_->window) out.emplace_back(impl_->poses[s].time, impl_->problem.pose(impl_->poses[s].var));
	return out;
}
std::map<std::int32_t, Eigen::Vector3d> SlidingWindowEstimator::landmarks() const
{
	std::map<std::int32_t, Eigen::Vector3d> out;
	for (const auto& [id, lm] : impl_->landmarks)
	{
		const Eigen::Vector3d x = Eigen::Map<const Eigen::Vector3d>(impl_->problem.value(lm.var));
		if (impl_->opt.landmarks == LandmarkParameterization::Xyz || lm.world_xyz)
			out[id] = x;
		else
		{
			const auto& a = impl_->poses[lm.anchor_step];
			out[id] = inverse_depth_to_world(impl_->problem.value(a.var), a.sensor, x);
		}
	}
	return out;
}
const eval::Trajectory& SlidingWindowEstimator::online_trajectory() const { return impl_->online; }
const eval::Trajectory& SlidingWindowEstimator::lagged_trajectory() const { return impl_->lagged; }
const std::vector<StepSummary>& SlidingWindowEstimator::step_summaries() const { return impl_->summaries; }
const SlidingWindowOptions& SlidingWindowEstimator::options() const { return impl_->opt; }

Eigen::MatrixXd SlidingWindowEstimator::prior_information() const
{
	return impl_->prior.J.transpose() * impl_->prior.J;
}

std::vector<std::pair<double, std::int32_t>> SlidingWindowEstimator::prior_variables() const
{
	std::vector<std::pair<double, std::int32_t>> out;
	for (VariableId v : impl_->prior.vars)
	{
		auto it = impl_->landmark_of_var.find(v);
		if (it != impl_->landmark_of_var.end())
		{
			out.emplace_back(-1.0, it->second);
			continue;
		}
		double t = -1;
		for (const auto& p : impl_->poses)
			if (p.var == v) t = p.time;
		out.emplace_back(t, -1);
	}
	return out;
}

Eigen::MatrixXd SlidingWindowEstimator::prior_gauge_directions() const
{
	const auto& I = *impl_;
	int n = 0;
	for (VariableId v : I.prior.vars) n += I.problem.variable(v).manifold->tangent_size();
	Eigen::MatrixXd N = Eigen::MatrixXd::Zero(n, 6);
	int off = 0;
	for (VariableId v : I.prior.vars)
	{
		const auto& var = I.problem.variable(v);
		const double* x = I.fej_or_current(v);
		if (var.manifold->tangent_size() == 6)
		{
			// Global motion x ↦ x + v + w × x seen as a right perturbation of T = [R | t]:
			// δρ = Rᵀ(v + w × t), δω = Rᵀ w.
			const auto T = se3_view(x);
			const Eigen::Matrix3d Rt = T.leftCols<3>().transpose();
			N.block<3, 3>(off, 0) = Rt;
			N.block<3, 3>(off, 3) = -Rt * skew(T.col(3));
			N.block<3, 3>(off + 3, 3) = Rt;
		}
		else if (I.opt.landmarks == LandmarkParameterization::Xyz || I.is_world_xyz_landmark(v))
		{
			const Eigen::Vector3d p(x[0], x[1], x[2]);
			N.block<3, 3>(off, 0) = Eigen::Matrix3d::Identity();
			N.block<3, 3>(off, 3) = -skew(p);
		}
		// Inverse-depth landmarks (still anchored) are anchor-relative: invariant under a global motion.
		off += var.manifold->tangent_size();
	}
	return N;
}

// ----------------------------------------------------------------------------------------------
BatchResult run_batch(const io::Rawlog& rawlog, const SlidingWindowOptions& options, int max_iterations)
{
	const auto t0 = Clock::now();
	SlidingWindowOptions o = options;
	o.window_size = 0;
	SlidingWindowEstimator est(o);
	est.impl_->solve_each_step = false;
	for (const auto& s : rawlog.steps) est.process(s);
	SolverOptions so = o.solver;
	so.max_iterations = max_iterations;
	so.function_tolerance = std::min(so.function_tolerance, 1e-12);
	BatchResult r;
	r.summary = solve(est.impl_->problem, so);
	for (std::size_t k = 1; k < est.impl_->poses.size(); k++)
		r.trajectory.push_back(est.impl_->poses[k].time, est.impl_->problem.pose(est.impl_->poses[k].var));
	r.seconds = seconds_since(t0);
	return r;
}

eval::Trajectory run_full_history_causal(const io::Rawlog& rawlog, const SlidingWindowOptions& options)
{
	SlidingWindowOptions o = options;
	o.window_size = 0;
	SlidingWindowEstimator est(o);
	for (const auto& s : rawlog.steps) est.process(s);
	return est.online_trajectory();
}
}  // namespace swba::estimators
