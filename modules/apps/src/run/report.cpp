// swba run: the comparison table, ape.txt / ape.csv / summary.json, TUM files and plots.
#include "../json_values.h"
#include "../report_helpers.h"
#include "covariance_files.h"
#include "output_dir.h"
#include "summary_fields.h"
#include "plots.h"

#include <swba/apps/run.h>
#include <swba/core/file.h>
#include <swba/eval/evaluation.h>
#include <swba/eval/ground_truth.h>
#include <swba/eval/plot.h>
#include <swba/eval/report.h>
#include <swba/eval/text_format.h>

#include <mrpt/system/filesystem.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace swba::apps
{
namespace
{
using detail::fixed;
using detail::pad_left;
using detail::pad_right;

/** The seven statistics evo computes, in the report's column order. */
const std::vector<std::pair<const char*, double eval::Statistics::*>>& stat_fields()
{
	static const std::vector<std::pair<const char*, double eval::Statistics::*>> f = {
		{"rmse", &eval::Statistics::rmse}, {"mean", &eval::Statistics::mean}, {"median", &eval::Statistics::median},
		{"max", &eval::Statistics::max},   {"min", &eval::Statistics::min},	  {"sse", &eval::Statistics::sse},
		{"std", &eval::Statistics::std}};
	return f;
}

/** The statistics blocks of a row, in the order of ape.txt, ape.csv and summary.json: name (CSV prefix),
 * JSON key, evo's title, and whether the row has them. */
struct StatsPart
{
	const char* name;
	const char* json_key;
	std::string title;
	eval::Statistics RunRow::*stats;
	bool RunRow::*has;
};

const std::vector<StatsPart>& stats_parts()
{
	using eval::PoseRelation;
	const std::string not_aligned = "\n(not aligned)";
	static const std::vector<StatsPart> parts = {
		{"trans", "ape_trans", eval::ape_metric_title(PoseRelation::TranslationPart) + not_aligned, &RunRow::ape_trans,
		 &RunRow::has_ape},
		{"full", "ape_full", eval::ape_metric_title(PoseRelation::FullTransformation) + not_aligned, &RunRow::ape_full,
		 &RunRow::has_ape},
		{"rot", "ape_rot", eval::ape_metric_title(PoseRelation::RotationAngleDeg) + not_aligned, &RunRow::ape_rot,
		 &RunRow::has_ape},
		{"rpe", "rpe_trans", eval::rpe_metric_title(PoseRelation::TranslationPart, 1, false) + not_aligned,
		 &RunRow::rpe_trans, &RunRow::has_rpe}};
	return parts;
}

void write_text_file(const std::string& path, const std::string& text, RunReport& report)
{
	write_text_file_atomically(path, text);
	report.files.push_back(path);
}
}  // namespace

std::string format_comparison_table(const RunReport& report)
{
	std::size_t wl = std::string("estimator").size(), ww = 5;  // label and W column widths
	for (const auto& r : report.rows)
	{
		wl = std::max(wl, r.label.size());
		ww = std::max(ww, std::to_string(r.window).size() + 2);
	}
	std::ostringstream s;
	s << "swba run: " << report.rawlog << " (" << report.steps << " steps)";
	if (report.ground_truth.empty()) s << ", no ground truth: APE not computed";
	s << "\nAPE not aligned; estimate after step k vs ground-truth row k+1; rot: APE rotation angle (deg); rpe: RPE "
		 "translation (m) between consecutive steps\n";
	const std::size_t cw = 11;
	s << pad_right("estimator", wl) << pad_left("W", ww) << "  " << pad_right("trajectory", 11)
	  << pad_left("trans rmse", cw) << pad_left("trans mean", cw) << pad_left("trans med", cw)
	  << pad_left("trans max", cw) << pad_left("full rmse", cw) << pad_left("rot rmse", cw) << pad_left("rpe rmse", cw)
	  << pad_left("ms/step", 10) << "\n";
	s << std::string(wl + ww + 2 + 11 + 7 * cw + 10, '-') << "\n";
	for (const auto& r : report.rows)
	{
		s << pad_right(r.label, wl) << pad_left(r.window ? std::to_string(r.window) : "-", ww) << "  "
		  << pad_right(r.trajectory, 11);
		if (r.has_ape && !r.diverged)
			s << pad_left(fixed(r.ape_trans.rmse, 6), cw) << pad_left(fixed(r.ape_trans.mean, 6), cw)
			  << pad_left(fixed(r.ape_trans.median, 6), cw) << pad_left(fixed(r.ape_trans.max, 6), cw)
			  << pad_left(fixed(r.ape_full.rmse, 6), cw) << pad_left(fixed(r.ape_rot.rmse, 6), cw);
		else
			for (int i = 0; i < 6; i++) s << pad_left("-", cw);
		s << pad_left(r.has_rpe && !r.diverged ? fixed(r.rpe_trans.rmse, 6) : "-", cw);
		s << pad_left(fixed(r.ms_per_step, 3), 10);
		if (r.interrupted)
			s << "  INTERRUPTED after " << r.failed_step << " steps";
		else if (r.failed)
			s << "  FAILED at step " << r.failed_step << ": " << r.failure;
		else if (r.diverged)
			s << "  DIVERGED (see the note)";
		s << "\n";
	}
	return s.str();
}

std::string format_ape_text(const RunReport& report)
{
	std::ostringstream s;
	for (const auto& r : report.rows)
	{
		s << "=== " << r.label << " (" << r.trajectory << ")";
		if (!r.file.empty()) s << ": " << r.file;
		s << "\n";
		if (r.failed) s << "FAILED at step " << r.failed_step << ": " << r.failure << "\n";
		if (r.diverged) s << "DIVERGED: " << r.divergence << " (figures below are not a result)\n";
		if (!r.has_ape)
		{
			s << "(no APE)\n\n";
			continue;
		}
		for (const auto& part : stats_parts())
			if (r.*part.has) s << eval::format_statistics_text(part.title, r.*part.stats) << "\n";
	}
	return s.str();
}

std::string format_ape_csv(const RunReport& report)
{
	std::ostringstream s;
	s << "label,name,window,trajectory,policy,fej,method,failed,failed_step,poses";
	for (const auto& part : stats_parts())
		for (const auto& [name, field] : stat_fields()) s << "," << part.name << "_" << name;
	s << ",association_correct_percent";
	for (const auto& f : association_fields()) s << ",association_" << f.first;
	s << ",seconds,ms_per_step,diverged,reading_misfit\n";
	char buf[64];
	auto num = [&buf](double v) {
		std::snprintf(buf, sizeof(buf), "%.9g", v);
		return std::string(buf);
	};
	for (const auto& r : report.rows)
	{
		s << eval::csv_field(r.label) << "," << r.name << "," << (r.window ? std::to_string(r.window) : "") << ","
		  << r.trajectory << "," << r.policy << "," << (r.fej ? (*r.fej ? "on" : "off") : "") << "," << r.method << ","
		  << (r.failed ? "true" : "false") << "," << (r.failed ? std::to_string(r.failed_step) : "") << ","
		  << r.estimate.size();
		for (const auto& part : stats_parts())
			for (const auto& f : stat_fields()) s << "," << (r.*part.has ? num((r.*part.stats).*(f.second)) : "");
		s << "," << (r.association ? num(100.0 * r.association->fraction_correct()) : "");
		for (const auto& f : association_fields())
			s << "," << (r.association ? std::to_string((*r.association).*(f.second)) : "");
		s << "," << num(r.seconds) << "," << num(r.ms_per_step) << "," << (r.diverged ? "true" : "false") << ","
		  << (r.reading_misfit ? num(*r.reading_misfit) : "") << "\n";
	}
	return s.str();
}

namespace
{
using nlohmann::ordered_json;

/** A JSON number, or null when `v` is not finite: JSON has no NaN / infinity (nlohmann would dump such a
 * double as null too; this states the contract instead of relying on it). */
ordered_json number(double v) { return std::isfinite(v) ? ordered_json(v) : ordered_json(nullptr); }

/** The seven statistics in stat_fields() order (no count). */
ordered_json stats_object(const eval::Statistics& s)
{
	ordered_json j = ordered_json::object();
	for (const auto& [name, field] : stat_fields()) j[name] = number(s.*field);
	return j;
}

ordered_json readings_object(const estimators::ReadingCounts& c)
{
	const std::pair<const char*, std::size_t> counts[] = {
		{"processed", c.readings},         {"gated", c.gated},
		{"readmitted", c.readmitted},      {"reassociated", c.reassociated},
		{"ambiguous", c.ambiguous},        {"rematched", c.rematched},
		{"unconfirmed", c.unconfirmed},
		{"excluded", c.excluded},          {"down_weighted", c.down_weighted},
		{"young_held_steps", c.young_held_steps}, {"association_cut", c.association_cut}};
	ordered_json j;
	for (const auto& [key, n] : counts) j[key] = n;
	return j;
}

/** How right the data association was (AssociationQuality), with the share correct in percent. */
ordered_json association_object(const estimators::AssociationQuality& q)
{
	ordered_json j;
	j["correct_percent"] = number(100.0 * q.fraction_correct());
	for (const auto& [name, field] : association_fields()) j[name] = q.*field;
	return j;
}

ordered_json nees_object(const RowNees& n)
{
	ordered_json o;
	o["poses"] = n.poses;
	o["position_mean"] = number(n.position_mean);
	o["position_dof"] = n.position_dof;
	o["position_in_band"] = number(n.position_in_band);
	o["pose_mean"] = number(n.pose_mean);
	o["pose_dof"] = n.pose_dof;
	o["pose_in_band"] = number(n.pose_in_band);
	return o;
}

/** One entry of "estimators"; fields that do not apply to the row are null. */
ordered_json row_object(const RunRow& r)
{
	ordered_json e;
	e["name"] = r.name;
	e["label"] = r.label;
	e["window"] = r.window ? ordered_json(r.window) : ordered_json(nullptr);
	e["trajectory"] = r.trajectory;
	e["policy"] = string_or_null(r.policy);
	e["fej"] = r.fej ? ordered_json(*r.fej) : ordered_json(nullptr);
	e["method"] = string_or_null(r.method);
	e["file"] = string_or_null(r.file);
	e["poses"] = r.estimate.size();
	for (const auto& part : stats_parts())
		e[part.json_key] = r.*part.has ? stats_object(r.*part.stats) : ordered_json(nullptr);
	e["association"] = r.association ? association_object(*r.association) : ordered_json(nullptr);
	e["seconds"] = number(r.seconds);
	e["ms_per_step"] = number(r.ms_per_step);
	e["covariance_seconds"] = r.covariance_seconds ? number(*r.covariance_seconds) : ordered_json(nullptr);
	e["steps_processed"] = r.steps;
	e["readings"] = r.reading_counts ? readings_object(*r.reading_counts) : ordered_json(nullptr);
	e["start"] = string_or_null(r.start);
	e["final_cost"] = r.final_cost ? number(*r.final_cost) : ordered_json(nullptr);
	e["diverged"] = r.diverged;
	e["divergence"] = r.diverged ? ordered_json(r.divergence) : ordered_json(nullptr);
	e["reading_misfit"] = r.reading_misfit ? number(*r.reading_misfit) : ordered_json(nullptr);
	e["nees"] = r.nees ? nees_object(*r.nees) : ordered_json(nullptr);
	e["failed"] = r.failed;
	e["failed_step"] = r.failed ? ordered_json(r.failed_step) : ordered_json(nullptr);
	e["failure"] = r.failed ? ordered_json(r.failure) : ordered_json(nullptr);
	e["interrupted"] = r.interrupted;
	return e;
}
}  // namespace

std::string format_summary_json(const RunReport& report)
{
	ordered_json j;
	j["rawlog"] = report.rawlog;
	j["ground_truth"] = string_or_null(report.ground_truth);
	j["steps"] = report.steps;
	j["landmarks"] = report.distinct_landmarks;
	j["readings"] = report.readings;
	j["skipped_readings"] = report.skipped_readings;
	j["readings_with_own_noise"] = report.readings_with_own_noise;
	j["estimators"] = ordered_json::array();
	for (const auto& r : report.rows) j["estimators"].push_back(row_object(r));
	// 2-space indentation, as eval's JSON files. Bytes that are not UTF-8 (a rawlog path, a failure
	// message) become U+FFFD instead of making dump() throw, so the file stays valid JSON.
	return j.dump(2, ' ', false, ordered_json::error_handler_t::replace) + "\n";
}

void write_run_files(const RunOptions& options, const std::vector<mrpt::poses::CPose3D>& gt, RunReport& report)
{
	const std::string& dir = options.out_dir;
	auto path = [&dir](const std::string& f) { return dir + "/" + f; };
	if (!gt.empty())
	{
		// Rows 0..steps: what the estimates are compared with.
		std::vector<mrpt::poses::CPose3D> used(gt.begin(), gt.begin() + static_cast<std::ptrdiff_t>(
																			 std::min(gt.size(), report.steps + 1)));
		eval::write_tum(path("gt.tum"), eval::ground_truth_trajectory(used));
		report.files.push_back(path("gt.tum"));
	}
	for (const auto& r : report.rows)
		if (!r.file.empty() && (!r.estimate.empty() || !r.failed))
		{
			eval::write_tum(path(r.file), r.estimate);
			report.files.push_back(path(r.file));
			if (r.covariance.empty() || r.covariance.size() != r.estimate.size()) continue;
			const auto [poses, landmarks] = covariance_file_names(r.file);
			write_text_file(path(poses), format_pose_covariances(r), report);
			write_text_file(path(landmarks), format_landmark_covariances(r), report);
		}
	write_text_file(path("ape.txt"), format_ape_text(report), report);
	write_text_file(path("ape.csv"), format_ape_csv(report), report);
	write_text_file(path("summary.json"), format_summary_json(report), report);
	RunOptions recorded = options;  // its paths absolute, so that the file reloads from any directory
	for (std::string* p : {&recorded.rawlog, &recorded.ground_truth, &recorded.association_truth, &recorded.ekf_ini})
		if (!p->empty()) *p = std::filesystem::absolute(*p).lexically_normal().string();
	write_text_file(path("config.ini"),
					"# swba run: the options of this run (load with --config)\n" + format_run_config(recorded), report);
	write_run_manifest(dir, report.files);
}

void write_run_outputs(const RunOptions& options, const std::vector<mrpt::poses::CPose3D>& gt, RunReport& report)
{
	const std::string& dir = options.out_dir;
	create_directory_or_throw(dir, "output directory");
	write_run_files(options, gt, report);

	if (!options.plots) return;
	// Without gnuplot the plots' data and scripts are still written: gnuplot elsewhere draws them.
	if (eval::find_gnuplot().empty())
		report.notes.push_back("gnuplot not found: plots not drawn; their data (.dat) and scripts (.gp) are in " + dir +
							   "/ and " + dir + "/plots/ (cd there && gnuplot <name>.gp)");
	write_run_plots(options, gt, report);
	write_run_manifest(dir, report.files);
}
}  // namespace swba::apps
