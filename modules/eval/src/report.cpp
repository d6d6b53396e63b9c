// Text / CSV / JSON reports of evaluation results.
#include "swba/eval/report.h"
#include "swba/eval/text_format.h"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace swba::eval
{
std::string json_string(const std::string& s)
{
	std::string out = "\"";
	for (unsigned char c : s)
	{
		switch (c)
		{
			case '"': out += "\\\""; break;
			case '\\': out += "\\\\"; break;
			case '\n': out += "\\n"; break;
			case '\t': out += "\\t"; break;
			case '\r': out += "\\r"; break;
			default:
				if (c < 0x20)
				{
					char buf[8];
					std::snprintf(buf, sizeof(buf), "\\u%04x", c);
					out += buf;
				}
				else
					out += static_cast<char>(c);
		}
	}
	return out + "\"";
}

std::string json_number(double v)
{
	if (!std::isfinite(v)) return "null";
	char buf[40];
	std::snprintf(buf, sizeof(buf), "%.17g", v);
	return buf;
}

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

std::string statistics_json(const Statistics& stats)
{
	std::string s = "{";
	for (const auto& [name, value] : statistics_items(stats)) s += json_string(name) + ":" + json_number(value) + ",";
	s += "\"count\":" + std::to_string(stats.count) + "}";
	return s;
}

namespace
{
/** Round-trip precision for machine-read files. */
std::string num(double v) { return format_significant(v, 17); }

std::ofstream open_for_writing(const std::string& path)
{
	std::ofstream f(path);
	if (!f) throw std::runtime_error("cannot write '" + path + "'");
	return f;
}

void finish(std::ofstream& f, const std::string& path)
{
	f.close();
	if (!f) throw std::runtime_error("error while writing '" + path + "'");
}



template <class Vec>
std::string json_array(const Vec& v)
{
	std::string s = "[";
	for (std::size_t i = 0; i < v.size(); i++) s += (i ? "," : "") + json_number(v[i]);
	return s + "]";
}
}  // namespace

void write_statistics_json(const std::string& path, const Statistics& stats)
{
	auto f = open_for_writing(path);
	f << statistics_json(stats) << "\n";
	finish(f, path);
}

std::string result_json(const MetricResult& r)
{
	std::ostringstream s;
	const Sim3& T = r.alignment.transform;
	std::vector<double> rot_rows;
	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++) rot_rows.push_back(T.R(i, j));
	std::vector<double> origin;
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++) origin.push_back(r.alignment.origin(i, j));
	s << "{\"metric\":" << json_string(r.metric) << ",\"title\":" << json_string(r.title)
	  << ",\"relation\":" << json_string(pose_relation_name(r.relation)) << ",\"unit\":" << json_string(r.unit)
	  << ",\"alignment\":{\"align\":" << (r.alignment_options.align ? "true" : "false")
	  << ",\"correct_scale\":" << (r.alignment_options.correct_scale ? "true" : "false")
	  << ",\"align_origin\":" << (r.alignment_options.align_origin ? "true" : "false")
	  << ",\"scale\":" << json_number(T.scale) << ",\"rotation_row_major\":" << json_array(rot_rows)
	  << ",\"translation\":" << json_array(std::vector<double>{T.t.x(), T.t.y(), T.t.z()})
	  << ",\"origin_transform_row_major\":" << json_array(origin) << "}"
	  << ",\"ref_input_poses\":" << r.ref_input_poses << ",\"est_input_poses\":" << r.est_input_poses
	  << ",\"associated_poses\":" << r.est.size() << ",\"stats\":" << statistics_json(r.stats)
	  << ",\"stamps\":" << json_array(r.stamps) << ",\"errors\":" << json_array(r.errors) << "}";
	return s.str();
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
	std::error_code ec;
	std::filesystem::create_directories(dir, ec);
	if (ec || !std::filesystem::is_directory(dir))
		throw std::runtime_error("cannot create results directory '" + dir + "'" + (ec ? ": " + ec.message() : ""));
	const auto path = [&](const std::string& name) { return (std::filesystem::path(dir) / (prefix + name)).string(); };
	std::vector<std::string> written;

	const std::string stats_json = path("_stats.json");
	write_statistics_json(stats_json, r.stats);
	written.push_back(stats_json);

	const std::string stats_csv = path("_stats.csv");
	{
		auto f = open_for_writing(stats_csv);
		write_statistics_csv(f, {{r.metric + " " + pose_relation_name(r.relation), r.stats}});
		finish(f, stats_csv);
	}
	written.push_back(stats_csv);

	const std::string errors_csv = path("_errors.csv");
	{
		auto f = open_for_writing(errors_csv);
		write_errors_csv(f, r);
		finish(f, errors_csv);
	}
	written.push_back(errors_csv);

	const std::string result = path("_result.json");
	{
		auto f = open_for_writing(result);
		f << result_json(r) << "\n";
		finish(f, result);
	}
	written.push_back(result);

	const std::string aligned = path("_est_aligned.tum");
	write_tum(aligned, r.est);
	written.push_back(aligned);
	return written;
}
}  // namespace swba::eval
