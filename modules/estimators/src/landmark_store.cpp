#include "landmark_store.h"

#include <algorithm>
#include <iterator>

namespace swba::estimators::detail
{
Landmark& LandmarkStore::add(Landmark lm)
{
	id_of_var_[lm.var] = lm.id;
	const std::int32_t id = lm.id;
	return records_.emplace(id, std::move(lm)).first->second;
}

Landmark* LandmarkStore::find(std::int32_t id)
{
	const auto it = records_.find(id);
	return it == records_.end() ? nullptr : &it->second;
}

const Landmark* LandmarkStore::find(std::int32_t id) const
{
	const auto it = records_.find(id);
	return it == records_.end() ? nullptr : &it->second;
}

const Landmark* LandmarkStore::find_by_variable(VariableId v) const
{
	const auto it = id_of_var_.find(v);
	return it == id_of_var_.end() ? nullptr : &records_.at(it->second);
}

void LandmarkStore::rebind(Landmark& lm, VariableId v)
{
	id_of_var_.erase(lm.var);
	lm.var = v;
	id_of_var_[v] = lm.id;
}

bool LandmarkStore::forget(VariableId v, std::size_t& held)
{
	const auto it = id_of_var_.find(v);
	if (it == id_of_var_.end()) return false;
	held = records_.at(it->second).held.size();
	records_.erase(it->second);
	id_of_var_.erase(it);
	return true;
}

void LandmarkStore::forget_observations(const std::set<FactorId>& removed)
{
	for (auto& [id, lm] : records_)
		lm.obs.erase(std::remove_if(lm.obs.begin(), lm.obs.end(),
									[&](const Observation& ob) { return removed.count(ob.factor) > 0; }),
					 lm.obs.end());
}

void LandmarkStore::hold_tail_readings(std::size_t k)
{
	std::vector<std::pair<std::int32_t, std::size_t>> read;
	for (auto& [id, lm] : records_)
	{
		const auto n = static_cast<std::size_t>(
			std::count_if(lm.obs.begin(), lm.obs.end(), [k](const Observation& o) { return o.pose_step == k; }));
		if (n == 0) continue;
		lm.tail_readings += n;
		read.emplace_back(id, n);
	}
	tail_readings_.push_back(std::move(read));
}

void LandmarkStore::release_tail_readings()
{
	if (tail_readings_.empty()) return;
	for (const auto& [id, n] : tail_readings_.front())
	{
		const auto it = records_.find(id);
		if (it != records_.end()) it->second.tail_readings -= std::min(n, it->second.tail_readings);
	}
	tail_readings_.pop_front();
}

LandmarkStore::Dropped LandmarkStore::drop_readings_at(std::size_t k)
{
	Dropped out;
	const auto at_k = [k](const Observation& o) { return o.pose_step == k; };
	for (auto& [id, lm] : records_)
	{
		const auto end = std::remove_if(lm.held.begin(), lm.held.end(), at_k);
		out.held += static_cast<std::size_t>(lm.held.end() - end);
		lm.held.erase(end, lm.held.end());
	}
	for (auto it = unconfirmed_.begin(); it != unconfirmed_.end();)
	{
		auto& w = it->second;
		const auto end = std::remove_if(w.begin(), w.end(), at_k);
		out.unconfirmed += static_cast<std::size_t>(w.end() - end);
		w.erase(end, w.end());
		it = w.empty() ? unconfirmed_.erase(it) : std::next(it);
	}
	return out;
}

LandmarkStore::Dropped LandmarkStore::drop_pending()
{
	Dropped out;
	for (auto& [id, lm] : records_)
	{
		out.held += lm.held.size();
		lm.held.clear();
	}
	for (const auto& [id, w] : unconfirmed_) out.unconfirmed += w.size();
	unconfirmed_.clear();
	return out;
}

const std::vector<Observation>* LandmarkStore::find_waiting(std::int32_t id) const
{
	const auto it = unconfirmed_.find(id);
	return it == unconfirmed_.end() ? nullptr : &it->second;
}

MapLandmark LandmarkStore::take_from_map(std::int32_t id)
{
	const MapLandmark m = map_.at(id);
	map_.erase(id);
	return m;
}
}  // namespace swba::estimators::detail
