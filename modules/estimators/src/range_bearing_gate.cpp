// The χ² gate of the range-bearing graph: which readings enter the window (on arrival, after each
// solve, or after each batch solve) and what the counts say. doc/outliers.md explains the choices.
#include "range_bearing_graph.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace swba::estimators::detail
{
double RangeBearingGraph::innovation_distance(const Eigen::Vector3d& p, std::size_t n, const Observation& o,
											  const Eigen::MatrixXd* pose_cov, const double* pose_x) const
{
	const auto& P = poses_[o.pose_step];
	return gate_.distance(p, n, o, P.sensor, pose_x ? pose_x : smoother_.problem().value(P.var), pose_cov);
}

void RangeBearingGraph::centre_gate(const std::vector<std::pair<std::int32_t, Observation>>& readings)
{
	std::vector<GatedReading> known;
	for (const auto& [id, o] : readings)
		if (const Landmark* lm = store_.find(id))
			known.push_back({world_position(*lm), LandmarkStore::window_readings(*lm), &o});
	const PoseRecord& newest = poses_.back();
	gate_.centre_on(*smoother_.problem().variable(newest.var).manifold, smoother_.problem().value(newest.var),
					newest.sensor, known);
}

Eigen::Vector3d RangeBearingGraph::world_position(const Landmark& lm) const
{
	const Eigen::Vector3d x = Eigen::Map<const Eigen::Vector3d>(smoother_.problem().value(lm.var));
	if (opt_.landmarks == LandmarkParameterization::Xyz || lm.world_xyz) return x;
	const auto& a = poses_[lm.anchor_step];
	return inverse_depth_to_world(smoother_.problem().value(a.var), a.sensor, x);
}

double RangeBearingGraph::gate_distance(const Landmark& lm, const Observation& o, const Eigen::MatrixXd* pose_cov,
									   const double* pose_x) const
{
	return innovation_distance(world_position(lm), LandmarkStore::window_readings(lm), o, pose_cov, pose_x);
}

void RangeBearingGraph::admit_reading(std::int32_t id, const Observation& o, StepSummary& sum)
{
	if (Landmark* found = store_.find(id))
	{
		Landmark& lm = *found;
		if (gate_distance(lm, o, &gate_.prediction_covariance(), gate_.centre()) <= gate_.threshold())
			admit(lm, o);
		else
		{
			lm.held.push_back(o);
			sum.gated++;
			counts_.gated++;
		}
		return;
	}
	// A landmark not in the graph: find the newest waiting first reading that agrees with this one.
	const Problem& problem = smoother_.problem();
	auto& waiting = store_.waiting(id);
	for (auto c = waiting.rbegin(); c != waiting.rend(); ++c)
	{
		const auto& C = poses_[c->pose_step];
		const Eigen::Vector3d p = inverse_depth_to_world(problem.value(C.var), C.sensor, inverse_depth_from_measurement(c->z));
		if (innovation_distance(p, 1, o, &gate_.prediction_covariance(), gate_.centre()) > gate_.threshold()) continue;
		Landmark& lm = add_landmark(id, *c);
		admit(lm, *c);
		admit(lm, o);
		// The others disagreed with this reading: held, re-tested after the solve like gated readings.
		for (const auto& other : waiting)
			if (&other != &*c) lm.held.push_back(other);
		sum.gated += static_cast<int>(waiting.size() - 1);
		counts_.gated += waiting.size() - 1;
		store_.confirm(id);
		return;
	}
	waiting.push_back(o);
}

void RangeBearingGraph::admit_associated(std::int32_t id, const Observation& o)
{
	if (Landmark* lm = store_.find(id))
	{
		admit(*lm, o);
		return;
	}
	// A provisional landmark: association gives each unmatched reading its own ID, so it waits alone.
	const std::vector<Observation>* waiting = store_.find_waiting(id);
	if (!waiting || waiting->size() != 1)
		throw std::logic_error("admit_associated: landmark " + std::to_string(id) + " is neither in the graph nor provisional");
	const Observation first = waiting->front();
	store_.confirm(id);
	Landmark& lm = add_landmark(id, first);
	admit(lm, first);
	admit(lm, o);
}

void RangeBearingGraph::readmit_held(StepSummary& sum)
{
	for (auto& [id, lm] : store_)
	{
		std::vector<Observation> still;
		for (const auto& h : lm.held)
			if (gate_distance(lm, h, nullptr) <= gate_.threshold())
			{
				admit(lm, h);
				sum.readmitted++;
				counts_.readmitted++;
			}
			else
				still.push_back(h);
		lm.held = std::move(still);
	}
}

void RangeBearingGraph::expire_readings_at(std::size_t k) { count_dropped(store_.drop_readings_at(k)); }

void RangeBearingGraph::finish_counts() { count_dropped(store_.drop_pending()); }

void RangeBearingGraph::count_dropped(const LandmarkStore::Dropped& d)
{
	counts_.excluded += d.held;
	counts_.unconfirmed += d.unconfirmed;
	counts_.excluded += d.unconfirmed;
}

bool RangeBearingGraph::regate_all()
{
	bool changed = false;
	for (auto& [id, lm] : store_)
	{
		std::vector<Observation> all = lm.obs;
		all.insert(all.end(), lm.held.begin(), lm.held.end());
		std::vector<double> d(all.size());
		for (std::size_t i = 0; i < all.size(); i++) d[i] = gate_distance(lm, all[i], nullptr);
		// A landmark keeps at least its best-fitting reading (a variable with no factor has no estimate).
		const std::size_t best = static_cast<std::size_t>(std::min_element(d.begin(), d.end()) - d.begin());
		std::vector<Observation> obs, held;
		for (std::size_t i = 0; i < all.size(); i++)
		{
			const bool in = d[i] <= gate_.threshold() || i == best;
			const bool was_in = all[i].factor >= 0;
			if (in == was_in)
			{
				(in ? obs : held).push_back(all[i]);
				continue;
			}
			changed = true;
			Observation o = all[i];
			if (in)
				o.factor = add_observation_factor(lm, o);
			else
			{
				smoother_.problem().remove_factor(o.factor);
				o.factor = -1;
			}
			(in ? obs : held).push_back(o);
		}
		lm.obs = std::move(obs);
		lm.held = std::move(held);
	}
	counts_.gated = 0;
	for (const auto& [id, lm] : store_) counts_.gated += lm.held.size();
	counts_.excluded = counts_.gated;
	return changed;
}

void RangeBearingGraph::set_reading_loss(std::shared_ptr<const LossFunction> loss)
{
	loss_ = std::move(loss);
	for (auto& [id, lm] : store_)
		for (auto& o : lm.obs)
		{
			smoother_.problem().remove_factor(o.factor);
			o.factor = add_observation_factor(lm, o);
		}
}

std::vector<double> RangeBearingGraph::robust_squared_residuals(const std::set<FactorId>& factors) const
{
	std::vector<double> out;
	if (!loss_) return out;
	const Problem& problem = smoother_.problem();
	for (FactorId f : factors)
	{
		const auto& fe = problem.factor(f);
		if (!fe.loss) continue;
		std::vector<const double*> x;
		for (VariableId v : fe.variables) x.push_back(problem.value(v));
		Eigen::VectorXd r(fe.factor->residual_dim());
		if (fe.factor->evaluate_whitened(x.data(), r.data(), nullptr)) out.push_back(r.squaredNorm());
	}
	return out;
}

int RangeBearingGraph::count_beyond_scale(const std::vector<double>& squares) const
{
	return static_cast<int>(
		std::count_if(squares.begin(), squares.end(), [this](double v) { return v > robust_scale_sq_; }));
}

int RangeBearingGraph::count_down_weighted(const std::set<FactorId>& factors) const
{
	return count_beyond_scale(robust_squared_residuals(factors));
}

std::set<FactorId> RangeBearingGraph::reading_factors_leaving(std::size_t k, const std::set<VariableId>& leaving) const
{
	std::set<FactorId> out;
	for (const auto& [id, lm] : store_)
		for (const auto& o : lm.obs)
			if (o.pose_step == k || leaving.count(lm.var)) out.insert(o.factor);
	return out;
}
}  // namespace swba::estimators::detail
