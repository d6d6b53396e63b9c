// Text / CSV / JSON reports of evaluation results.
#include "swba/eval/report.h"
#include "swba/eval/text_format.h"
#include <swba/core/file.h>

#include <nlohmann/json.hpp>

#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace swba::eval
{
std::string format_statistics_text(const std::string& title, const Statistics& stats)
{
	std::string s = title + "\n\n";
	char buf[96];
	for (const auto& [name, value] : statistics_items(stats))
	{
		std::snprintf(buf, sizeof(buf), "%10s\t%.6f\n", name.c_str(), value);
		s += buf;
	}
	return s;
}

std::string format_text_report(const MetricResult& result) { return format_statistics_text(result.title, result.stats); }

namespace
{
using nlohmann::ordered_json;

/** Round-trip precision for machine-read files. */
std::string num(double v) { return format_significant(v, 17); }


/** A JSON number, or null when `v` is not finite (JSON has no NaN / infinity). nlohmann would dump a
 * non-finite double as null too; saying so here keeps that contract independent of the library. */
ordered_json number(double v) { return std::isfinite(v) ? ordered_json(v) : ordered_json(nullptr); }

template <class Vec>
ordered_json number_array(const Vec& v)
{
	ordered_json a = ordered_json::array();
	for (const double x : v) a.push_back(number(x));
	return a;
}

/** The statistics in statistics_items() order, then "count". */
ordered_json statistics_object(const Statistics& stats)
{
	ordered_json j = ordered_json::object();
	for (const auto& [name, value] : statistics_items(stats)) j[name] = number(value);
	j["count"] = stats.count;
	return j;
}

ordered_json alignment_object(const MetricResult& r)
{
	const Sim3& T = r.alignment.transform;
	std::vector<double> rot_rows, origin;
	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++) rot_rows.push_back(T.R(i, j));
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++) origin.push_back(r.alignment.origin(i, j));
	ordered_json a;
	a["align"] = r.alignment_options.align;
	a["correct_scale"] = r.alignment_options.correct_scale;
	a["align_origin"] = r.alignment_options.align_origin;
	a["scale"] = number(T.scale);
	a["rotation_row_major"] = number_array(rot_rows);
	a["translation"] = number_array(std::vector<double>{T.t.x(), T.t.y(), T.t.z()});
	a["origin_transform_row_major"] = number_array(origin);
	return a;
}

/** The text of a JSON file: 2-space indentation. Bytes that are not UTF-8 (e.g. in a file name) become
 * U+FFFD instead of making dump() throw, so the file stays valid JSON. */
std::string json_text(const ordered_json& j) { return j.dump(2, ' ', false, ordered_json::error_handler_t::replace); }
}  // namespace

std::string statistics_json(const Statistics& stats) { return json_text(statistics_object(stats)); }

void write_statistics_json(const std::string& path, const Statistics& stats)
{
	write_file_atomically(path, [&](std::ostream& f) { f << statistics_json(stats) << "\n"; });
}

std::string result_json(const MetricResult& r)
{
	ordered_json j;
	j["metric"] = r.metric;
	j["title"] = r.title;
	j["relation"] = pose_relation_name(r.relation);
	j["unit"] = r.unit;
	j["alignment"] = alignment_object(r);
	j["ref_input_poses"] = r.ref_input_poses;
	j["est_input_poses"] = r.est_input_poses;
	j["associated_poses"] = r.est.size();
	j["stats"] = statistics_object(r.stats);
	j["stamps"] = number_array(r.stamps);
	j["errors"] = number_array(r.errors);
	return json_text(j);
}

void write_errors_csv(std::ostream& out, const MetricResult& r)
{
	out << "t,error,ref_x,ref_y,ref_z,est_x,est_y,est_z\n";
	for (std::size_t k = 0; k < r.errors.size(); k++)
	{
		const std::size_t i = r.pose_ids.at(k);
		const auto& a = r.ref.poses.at(i);
		const auto& b = r.est.poses.at(i);
		out << num(r.stamps.at(k)) << ',' << num(r.errors[k]) << ',' << num(a.x()) << ',' << num(a.y()) << ','
			<< num(a.z()) << ',' << num(b.x()) << ',' << num(b.y()) << ',' << num(b.z()) << '\n';
	}
}

void write_statistics_csv(std::ostream& out, const std::vector<std::pair<std::string, Statistics>>& rows)
{
	out << "name,count";
	const Statistics dummy;
	for (const auto& item : statistics_items(dummy)) out << ',' << item.first;
	out << '\n';
	for (const auto& [name, stats] : rows)
	{
		out << csv_field(name) << ',' << stats.count;
		for (const auto& item : statistics_items(stats)) out << ',' << num(item.second);
		out << '\n';
	}
}

std::vector<std::string> save_results(const MetricResult& r, const std::string& dir, const std::string& prefix_in)
{
	std::string prefix = prefix_in;
	if (prefix.empty())
		for (char c : r.metric) prefix += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
	create_directory_or_throw(dir, "results directory");
	const auto path = [&](const std::string& name) { return (std::filesystem::path(dir) / (prefix + name)).string(); };
	std::vector<std::string> written;

	const std::string stats_json = path("_stats.json");
	write_statistics_json(stats_json, r.stats);
	written.push_back(stats_json);

	const std::string stats_csv = path("_stats.csv");
	write_file_atomically(stats_csv, [&](std::ostream& f) {
		write_statistics_csv(f, {{r.metric + " " + pose_relation_name(r.relation), r.stats}});
	});
	written.push_back(stats_csv);

	const std::string errors_csv = path("_errors.csv");
	write_file_atomically(errors_csv, [&](std::ostream& f) { write_errors_csv(f, r); });
	written.push_back(errors_csv);

	const std::string result = path("_result.json");
	write_file_atomically(result, [&](std::ostream& f) { f << result_json(r) << "\n"; });
	written.push_back(result);

	const std::string aligned = path("_est_aligned.tum");
	write_tum(aligned, r.est);
	written.push_back(aligned);
	return written;
}
}  // namespace swba::eval
