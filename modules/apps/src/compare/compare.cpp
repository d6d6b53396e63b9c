// swba compare: paired ratios of two sets of swba run results (see compare.h).
#include <swba/apps/compare.h>

#include "../report_helpers.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <ostream>
#include <sstream>
#include <stdexcept>

namespace swba::apps
{
namespace fs = std::filesystem;
using detail::fixed;
using nlohmann::ordered_json;

namespace
{
std::string metric_title(CompareMetric m)
{
	switch (m)
	{
		case CompareMetric::ApeRot: return "APE rotation angle rmse (deg)";
		case CompareMetric::RpeTrans: return "RPE translation rmse (m)";
		case CompareMetric::ApeTrans: break;
	}
	return "APE translation rmse (m)";
}

/** The statistics object of `metric` in one row, or nullptr (range-bearing and inertial summaries
 * name the rotation APE differently). */
const ordered_json* metric_object(const ordered_json& row, CompareMetric metric)
{
	const auto object = [&row](const char* key) { return row.contains(key) && row.at(key).is_object() ? &row.at(key) : nullptr; };
	switch (metric)
	{
		case CompareMetric::ApeRot:
			if (const ordered_json* o = object("ape_rot")) return o;
			return object("ape_rot_deg");
		case CompareMetric::RpeTrans: return object("rpe_trans");
		case CompareMetric::ApeTrans: break;
	}
	return object("ape_trans");
}

bool flag(const ordered_json& row, const char* key) { return row.contains(key) && row.at(key).is_boolean() && row.at(key).get<bool>(); }

ResultFigure figure_of(const ordered_json& row, CompareMetric metric, const std::string& source)
{
	ResultFigure f;
	f.source = source;
	for (const char* s : {"failed", "diverged", "interrupted"})
		if (flag(row, s)) f.status = s;
	if (!f.status.empty()) return f;
	const ordered_json* stats = metric_object(row, metric);
	if (stats && stats->contains("rmse") && stats->at("rmse").is_number() && std::isfinite(stats->at("rmse").get<double>()))
		f.value = stats->at("rmse").get<double>();
	else
		f.status = "no figure";
	return f;
}

bool same_figure(const ResultFigure& a, const ResultFigure& b) { return a.value == b.value && a.status == b.status; }

/** The key of a row: its label, without the start a batch row names ("batch (DR start)" → "batch"), so
 * that the batch rows pair whatever start each rawlog's batch took. */
std::string row_key(const ordered_json& row)
{
	std::string label = row.at("label").get<std::string>();
	const std::string suffix = " start)";
	const std::size_t open = label.rfind(" (");
	if (row.contains("start") && row.at("start").is_string() && open != std::string::npos && label.size() > suffix.size() &&
		label.compare(label.size() - suffix.size(), suffix.size(), suffix) == 0)
		label.erase(open);
	return label;
}

/** Adds one summary's rows to `set`; returns their keys in the summary's order. */
std::vector<std::string> add_summary(ResultSet& set, const fs::path& file, CompareMetric metric)
{
	const std::string src = file.string();
	std::ifstream in(file);
	if (!in) throw std::runtime_error(src + ": cannot be read");
	ordered_json j;
	try
	{
		j = ordered_json::parse(in);
	}
	catch (const nlohmann::json::exception& e)
	{
		throw std::runtime_error(src + ": not JSON (" + e.what() + ")");
	}
	const char* rows_key = j.contains("estimators") ? "estimators" : "rows";
	if (!j.is_object() || !j.contains("rawlog") || !j.at("rawlog").is_string() || !j.contains(rows_key) ||
		!j.at(rows_key).is_array())
		throw std::runtime_error(src + ": not a swba run summary (needs \"rawlog\" and \"estimators\" or \"rows\")");
	auto& rows = set.figures[j.at("rawlog").get<std::string>()];
	std::vector<std::string> keys;
	for (const auto& row : j.at(rows_key))
	{
		if (!row.contains("label") || !row.at("label").is_string())
			throw std::runtime_error(src + ": a row without a \"label\"");
		const std::string label = row_key(row);
		keys.push_back(label);
		const ResultFigure f = figure_of(row, metric, src);
		const auto it = rows.find(label);
		if (it == rows.end())
			rows.emplace(label, f);
		else if (!same_figure(it->second, f))
			throw std::runtime_error("two summaries of rawlog " + j.at("rawlog").get<std::string>() + " give '" + label +
									 "' different figures: " + it->second.source + " and " + src +
									 " (compare one configuration per side)");
	}
	set.summaries++;
	return keys;
}

std::string signed_fixed(double v, int digits) { return (v >= 0 ? "+" : "") + fixed(v, digits); }

std::vector<std::string> one_side_only(const ResultSet& a, const ResultSet& b)
{
	std::vector<std::string> out;
	for (const auto& [rawlog, rows] : a.figures)
		if (!b.figures.count(rawlog)) out.push_back(rawlog);
	return out;
}

/** The table; setw counts bytes, so the header's two-byte "±" has one more. */
std::string format_paired_table(const std::vector<PairedComparison>& rows)
{
	std::ostringstream s;
	s << std::left << std::setw(26) << "estimator" << std::right << std::setw(6) << "pairs" << std::setw(14)
	  << "base geomean" << std::setw(15) << "other geomean" << std::setw(9) << "ratio" << std::setw(25)
	  << "mean ln ratio ± s.e." << std::setw(8) << "better" << std::setw(7) << "worse" << std::setw(7) << "equal" << "\n";
	for (const auto& c : rows)
	{
		const std::string se = c.log_ratio_std_error ? fixed(*c.log_ratio_std_error, 4) : "-";
		s << std::left << std::setw(26) << c.label << std::right << std::setw(6) << c.rawlogs.size() << std::setw(14)
		  << fixed(c.base_geomean, 6) << std::setw(15) << fixed(c.other_geomean, 6) << std::setw(9)
		  << fixed(std::exp(c.mean_log_ratio), 4) << std::setw(15) << signed_fixed(c.mean_log_ratio, 4) << " ± "
		  << std::left << std::setw(6) << se << std::right << std::setw(8) << c.better << std::setw(7) << c.worse
		  << std::setw(7) << c.equal << "\n";
	}
	return s.str();
}

std::string format_paired_rawlogs(const PairedComparison& c)
{
	std::ostringstream s;
	s << c.label << ":\n";
	for (std::size_t i = 0; i < c.rawlogs.size(); i++)
		s << "  " << c.rawlogs[i] << "  " << fixed(c.base[i], 6) << " -> " << fixed(c.other[i], 6) << "  ("
		  << fixed(c.other[i] / c.base[i], 4) << ")\n";
	return s.str();
}

ordered_json comparison_json(const PairedComparison& c)
{
	ordered_json pairs = ordered_json::array();
	for (std::size_t i = 0; i < c.rawlogs.size(); i++)
		pairs.push_back({{"rawlog", c.rawlogs[i]}, {"base", c.base[i]}, {"other", c.other[i]}});
	const ordered_json se = c.log_ratio_std_error ? ordered_json(*c.log_ratio_std_error) : ordered_json(nullptr);
	return {{"label", c.label}, {"pairs", c.rawlogs.size()}, {"base_geomean", c.base_geomean},
			{"other_geomean", c.other_geomean}, {"ratio", std::exp(c.mean_log_ratio)},
			{"mean_log_ratio", c.mean_log_ratio}, {"log_ratio_std_error", se}, {"better", c.better},
			{"worse", c.worse}, {"equal", c.equal}, {"no_figure_base_only", c.no_figure_base},
			{"no_figure_other_only", c.no_figure_other}, {"no_figure_both", c.no_figure_both}, {"rawlogs", pairs}};
}

/** What the table leaves out, one line each: rawlogs and rows on one side only, missing figures. */
void write_notes(const ResultSet& base, const ResultSet& other, const std::vector<PairedComparison>& rows,
				 std::ostream& log)
{
	for (const auto& [side, list] : {std::pair{"base", one_side_only(base, other)}, {"other", one_side_only(other, base)}})
		if (!list.empty())
		{
			log << "note: " << list.size() << " rawlog" << (list.size() == 1 ? "" : "s") << " only in " << side
				<< ", not compared:";
			for (const auto& r : list) log << " " << r;
			log << "\n";
		}
	for (const auto& [side, a, b] : {std::tuple{"base", &base, &other}, {"other", &other, &base}})
		for (const auto& l : a->labels)
			if (std::find(b->labels.begin(), b->labels.end(), l) == b->labels.end())
				log << "note: '" << l << "' only in " << side << ", not compared\n";
	for (const auto& c : rows)
		if (c.no_figure_base + c.no_figure_other + c.no_figure_both > 0)
			log << "note: " << c.label << ": rawlogs without a figure (failed, diverged, interrupted or none): "
				<< c.no_figure_base << " in base only, " << c.no_figure_other << " in other only, " << c.no_figure_both
				<< " in both; not in the ratios\n";
}
}  // namespace

ResultSet read_results(const std::string& path, CompareMetric metric)
{
	std::error_code ec;
	if (!fs::exists(path, ec)) throw std::runtime_error(path + ": does not exist");
	std::vector<fs::path> files;
	if (fs::is_directory(path, ec))
	{
		for (const auto& e : fs::recursive_directory_iterator(path, fs::directory_options::skip_permission_denied, ec))
			if (e.is_regular_file() && e.path().filename() == "summary.json") files.push_back(e.path());
		if (ec) throw std::runtime_error(path + ": cannot be listed (" + ec.message() + ")");
	}
	else
		files.push_back(path);
	std::sort(files.begin(), files.end());
	if (files.empty()) throw std::runtime_error(path + ": no summary.json below it (give swba run's --out directory or a sweep)");
	ResultSet set;
	std::vector<std::vector<std::string>> keys;
	for (const auto& f : files) keys.push_back(add_summary(set, f, metric));
	// Row order: that of the summary with the most rows first (a sweep's merge: swba run's order).
	std::stable_sort(keys.begin(), keys.end(), [](const auto& a, const auto& b) { return a.size() > b.size(); });
	for (const auto& list : keys)
		for (const auto& k : list)
			if (std::find(set.labels.begin(), set.labels.end(), k) == set.labels.end()) set.labels.push_back(k);
	return set;
}

PairedComparison compare_label(const ResultSet& base, const ResultSet& other, const std::string& label)
{
	PairedComparison c;
	c.label = label;
	double sum_lb = 0, sum_lo = 0;
	std::vector<double> logs;
	for (const auto& [rawlog, rows] : base.figures)
	{
		const auto o = other.figures.find(rawlog);
		if (o == other.figures.end()) continue;
		const auto fb = rows.find(label), fo = o->second.find(label);
		if (fb == rows.end() || fo == o->second.end()) continue;
		const auto& b = fb->second.value;
		const auto& x = fo->second.value;
		// A figure of zero has no ratio: it counts as missing, as a failed row does.
		const bool has_b = b && *b > 0, has_o = x && *x > 0;
		if (!has_b || !has_o)
		{
			(has_b ? c.no_figure_other : has_o ? c.no_figure_base : c.no_figure_both)++;
			continue;
		}
		c.rawlogs.push_back(rawlog);
		c.base.push_back(*b);
		c.other.push_back(*x);
		logs.push_back(std::log(*x / *b));
		sum_lb += std::log(*b);
		sum_lo += std::log(*x);
		(*x < *b ? c.better : *x > *b ? c.worse : c.equal)++;
	}
	const double n = static_cast<double>(logs.size());
	if (logs.empty()) return c;
	c.base_geomean = std::exp(sum_lb / n);
	c.other_geomean = std::exp(sum_lo / n);
	for (double v : logs) c.mean_log_ratio += v / n;
	if (logs.size() >= 2)
	{
		double ss = 0;
		for (double v : logs) ss += (v - c.mean_log_ratio) * (v - c.mean_log_ratio);
		c.log_ratio_std_error = std::sqrt(ss / (n - 1) / n);
	}
	return c;
}

int run_compare(const CompareOptions& o, std::ostream& out, std::ostream& log)
{
	const ResultSet base = read_results(o.base, o.metric), other = read_results(o.other, o.metric);
	std::vector<PairedComparison> rows;
	for (const auto& l : base.labels)
		if (std::find(other.labels.begin(), other.labels.end(), l) != other.labels.end())
		{
			PairedComparison c = compare_label(base, other, l);
			if (!c.rawlogs.empty() || c.no_figure_base + c.no_figure_other + c.no_figure_both > 0) rows.push_back(c);
		}
	std::vector<PairedComparison> shown;
	for (const auto& c : rows)
		if (!c.rawlogs.empty()) shown.push_back(c);
	if (shown.empty())
		throw std::runtime_error("no rawlog and estimator with a figure on both sides (base " + o.base + ": " +
								 std::to_string(base.figures.size()) + " rawlogs, other " + o.other + ": " +
								 std::to_string(other.figures.size()) + "); rawlogs are matched by the path their "
								 "summary.json names");
	out << metric_title(o.metric) << ", other / base paired by rawlog; base " << o.base << " (" << base.summaries
		<< " summaries, " << base.figures.size() << " rawlogs), other " << o.other << " (" << other.summaries
		<< " summaries, " << other.figures.size() << " rawlogs)\n";
	out << format_paired_table(shown);
	if (o.per_rawlog)
		for (const auto& c : shown) out << "\n" << format_paired_rawlogs(c);
	write_notes(base, other, rows, log);
	if (!o.json_path.empty())
	{
		ordered_json est = ordered_json::array();
		for (const auto& c : rows) est.push_back(comparison_json(c));
		const ordered_json j = {{"metric", enum_name(o.metric)}, {"base", o.base}, {"other", o.other},
								{"estimators", est}, {"base_only_rawlogs", one_side_only(base, other)},
								{"other_only_rawlogs", one_side_only(other, base)}};
		std::ofstream f(o.json_path);
		if (!(f << j.dump(2) << "\n")) throw std::runtime_error(o.json_path + ": cannot be written");
		log << "swba compare: wrote " << o.json_path << "\n";
	}
	return 0;
}
}  // namespace swba::apps
