// Reading a job's summary.json back (see summary_json.h).
#include "summary_json.h"

#include "../run/summary_fields.h"


#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <vector>

namespace swba::apps
{
namespace
{
std::string string_or_empty(const ordered_json& e, const char* key)
{
	const auto& v = e.at(key);
	return v.is_null() ? "" : v.get<std::string>();
}

double number_or_nan(const ordered_json& v) { return v.is_null() ? std::nan("") : v.get<double>(); }

eval::Statistics statistics(const ordered_json& s, std::size_t count)
{
	eval::Statistics st;
	st.count = count;
	st.rmse = number_or_nan(s.at("rmse"));
	st.mean = number_or_nan(s.at("mean"));
	st.median = number_or_nan(s.at("median"));
	st.max = number_or_nan(s.at("max"));
	st.min = number_or_nan(s.at("min"));
	st.sse = number_or_nan(s.at("sse"));
	st.std = number_or_nan(s.at("std"));
	return st;
}
}  // namespace

namespace
{
/** Whether `key` is in `e` and not null (the rotation APE, RPE and association of a summary.json are
 * optional: a job written before they were reported has none). */
bool present(const ordered_json& e, const char* key) { return e.contains(key) && !e.at(key).is_null(); }

/** An "association" object of summary.json (its counts; the percentage is derived from them). */
estimators::AssociationQuality association_quality(const ordered_json& a)
{
	estimators::AssociationQuality q;
	for (const auto& [name, field] : association_fields()) q.*field = a.at(name).get<std::size_t>();
	return q;
}
}  // namespace

RunRow run_row_from_json(const ordered_json& e, const std::string& dir, const std::string& source)
{
	RunRow r;
	try
	{
		r.name = e.at("name").get<std::string>();
		r.label = e.at("label").get<std::string>();
		r.window = e.at("window").is_null() ? 0 : e.at("window").get<int>();
		r.trajectory = e.at("trajectory").get<std::string>();
		r.policy = string_or_empty(e, "policy");
		if (!e.at("fej").is_null()) r.fej = e.at("fej").get<bool>();
		r.method = string_or_empty(e, "method");
		r.file = string_or_empty(e, "file");
		const auto poses = e.at("poses").get<std::size_t>();
		r.has_ape = !e.at("ape_trans").is_null();
		if (r.has_ape)
		{
			r.ape_trans = statistics(e.at("ape_trans"), poses);
			r.ape_full = statistics(e.at("ape_full"), poses);
			if (present(e, "ape_rot")) r.ape_rot = statistics(e.at("ape_rot"), poses);
		}
		r.has_rpe = present(e, "rpe_trans");
		if (r.has_rpe) r.rpe_trans = statistics(e.at("rpe_trans"), poses - 1);
		if (present(e, "association")) r.association = association_quality(e.at("association"));
		r.seconds = number_or_nan(e.at("seconds"));
		r.ms_per_step = number_or_nan(e.at("ms_per_step"));
		r.steps = e.at("steps_processed").get<std::size_t>();
		r.failed = e.at("failed").get<bool>();
		if (r.failed) r.failed_step = e.at("failed_step").get<std::size_t>();
		r.failure = string_or_empty(e, "failure");
		r.interrupted = e.at("interrupted").get<bool>();
		if (!r.file.empty() && std::filesystem::exists(dir + "/" + r.file)) r.estimate = eval::read_tum(dir + "/" + r.file);
		if (r.estimate.size() != poses)
			throw std::runtime_error(r.file + " has " + std::to_string(r.estimate.size()) + " poses, summary.json says " +
									 std::to_string(poses));
	}
	catch (const nlohmann::json::exception& x)
	{
		throw std::runtime_error(source + ": estimator '" + r.label + "': " + x.what());
	}
	catch (const std::runtime_error& x)
	{
		throw std::runtime_error(source + ": estimator '" + r.label + "': " + x.what());
	}
	return r;
}

std::string covariance_file_name(const std::string& tum_file)
{
	const std::string ext = ".tum";
	if (tum_file.size() > ext.size() && tum_file.compare(tum_file.size() - ext.size(), ext.size(), ext) == 0)
		return tum_file.substr(0, tum_file.size() - ext.size()) + ".cov";
	return tum_file + ".cov";
}

std::string find_covariance_file(const std::string& dir, const RunRow& row)
{
	if (row.file.empty()) return "";
	std::vector<std::string> names = {covariance_file_name(row.file)};
	if (row.name == "ekf" && !row.method.empty()) names.push_back("ekf_" + row.method + ".cov");
	for (const auto& n : names)
		if (std::filesystem::exists(dir + "/" + n)) return dir + "/" + n;
	return "";
}

std::vector<JobSummary> check_mergeable(const SweepPlan& plan, SweepKind kind, const std::string& what,
										std::ostream& log)
{
	if (plan.kind != kind) throw std::invalid_argument("not a " + what + " sweep");
	return read_complete_jobs(plan, log);
}
}  // namespace swba::apps
