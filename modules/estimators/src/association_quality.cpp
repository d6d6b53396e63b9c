// Association quality against the truth (doc/association.md).
#include <swba/estimators/association_quality.h>

#include <swba/factors/range_bearing.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace swba::estimators
{
namespace
{
/** Calls f(true ID, assigned ID) for every reading of `truth` (assigned −1 where `assigned` has none). */
template <typename F>
void for_each_reading(const ReadingIds& assigned, const ReadingIds& truth, F f)
{
	for (std::size_t k = 0; k < truth.size(); k++)
		for (std::size_t i = 0; i < truth[k].size(); i++)
			f(truth[k][i], k < assigned.size() && i < assigned[k].size() ? assigned[k][i] : -1);
}
}  // namespace

AssociationQuality evaluate_association(const ReadingIds& assigned, const ReadingIds& truth)
{
	// Readings per estimated landmark, by true landmark.
	std::map<std::int32_t, std::map<std::int32_t, std::size_t>> votes;
	std::map<std::int32_t, std::size_t> size;
	AssociationQuality q;
	std::map<std::int32_t, bool> seen_true;
	for_each_reading(assigned, truth, [&](std::int32_t t, std::int32_t a) {
		if (a >= 0) size[a]++;
		if (t < 0) return;
		q.readings++;
		seen_true[t] = true;
		if (a >= 0) votes[a][t]++;
	});
	q.true_landmarks = seen_true.size();
	std::map<std::int32_t, std::int32_t> stands_for;             // confirmed estimated → true
	std::map<std::int32_t, std::pair<std::size_t, std::int32_t>> primary;  // true → (readings, estimated)
	for (const auto& [a, n] : size)
	{
		if (n < 2) continue;
		q.landmarks++;
		std::int32_t best = -1;
		std::size_t best_votes = 0;
		for (const auto& [t, v] : votes[a])
			if (v > best_votes) best = t, best_votes = v;  // map order: ties keep the smallest ID
		if (best < 0 || 2 * best_votes < n) q.spurious++;
		if (best < 0) continue;
		stands_for[a] = best;
		auto it = primary.find(best);
		if (it == primary.end() || n > it->second.first) primary[best] = {n, a};
	}
	for (const auto& [a, t] : stands_for)
		if (primary.at(t).second != a) q.duplicates++;
	for_each_reading(assigned, truth, [&](std::int32_t t, std::int32_t a) {
		if (t < 0 || a < 0 || !stands_for.count(a)) return;
		q.associated++;
		const auto p = primary.find(t);
		if (p != primary.end() && p->second.second == a) q.correct++;
	});
	return q;
}

ReadingIds reading_ids(const io::Rawlog& rawlog)
{
	ReadingIds out(rawlog.steps.size());
	for (std::size_t k = 0; k < rawlog.steps.size(); k++)
		for (const auto& r : rawlog.steps[k].readings) out[k].push_back(r.landmark_id);
	return out;
}

std::map<std::int32_t, Eigen::Vector3d> read_landmark_ground_truth(const std::string& path)
{
	std::ifstream f(path);
	if (!f) throw std::runtime_error(path + ": cannot open the landmark ground truth");
	std::map<std::int32_t, Eigen::Vector3d> out;
	std::string line;
	for (int line_no = 1; std::getline(f, line); line_no++)
	{
		const auto first = line.find_first_not_of(" \t\r");
		if (first == std::string::npos || line[first] == '#' || line[first] == '%') continue;  // blank, comment
		std::istringstream in(line);
		std::vector<double> v;
		double x;
		while (in >> x) v.push_back(x);
		const bool finite = std::all_of(v.begin(), v.end(), [](double d) { return std::isfinite(d); });
		if (!in.eof() || !finite || v.size() < 4 ||
			v.back() != static_cast<double>(static_cast<std::int32_t>(v.back())))
			throw std::runtime_error(path + ":" + std::to_string(line_no) +
									 ": expected x y z ... id (finite numbers, the ID last and an integer)");
		out[static_cast<std::int32_t>(v.back())] = {v[0], v[1], v[2]};
	}
	if (out.empty()) throw std::runtime_error(path + ": no landmark in the ground truth");
	return out;
}

ReadingIds true_landmarks_of_readings(const io::Rawlog& rawlog, const std::vector<mrpt::poses::CPose3D>& robot_path,
									  const std::map<std::int32_t, Eigen::Vector3d>& landmarks, double max_distance)
{
	ReadingIds out(rawlog.steps.size());
	for (std::size_t k = 0; k < rawlog.steps.size(); k++)
	{
		const auto& st = rawlog.steps[k];
		for (const auto& r : st.readings)
		{
			std::int32_t best = -1;
			if (k + 1 < robot_path.size())
			{
				const Eigen::Vector3d p = inverse_depth_to_world(robot_path[k + 1], st.sensor_pose,
																 inverse_depth_from_measurement({r.range, r.yaw, r.pitch}));
				double d_best = max_distance;
				for (const auto& [id, q] : landmarks)
				{
					const double d = (q - p).norm();
					if (d <= d_best) best = id, d_best = d;
				}
			}
			out[k].push_back(best);
		}
	}
	return out;
}
}  // namespace swba::estimators
