// swba merge of a run sweep: the jobs' summary.json files back into swba run's outputs (see sweep.h).
#include "../run/plots.h"
#include "summary_json.h"

#include <swba/apps/sweep.h>
#include <swba/core/file.h>
#include <swba/eval/ground_truth.h>
#include <swba/eval/plot.h>
#include <swba/eval/text_format.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace swba::apps
{
namespace fs = std::filesystem;

namespace
{
/** The rows of a rawlog's jobs in the order one `swba run` makes them: the EKF rows, then per landmark
 * policy × FEJ setting the window rows of each W (online, lagged), then batch and causal. Each with the
 * job and its index there. */
struct MergedRow
{
	std::size_t job = 0, index = 0;	 ///< which job, which of its "estimators"
	ordered_json entry;
};

std::vector<MergedRow> merged_estimators(const std::vector<JobSummary>& jobs)
{
	for (const auto& j : jobs)
		for (const auto& e : j.json.at("estimators"))
		{
			const std::string name = e.at("name").get<std::string>();
			if (name != "ekf" && name != "window" && name != "batch" && name != "batch_alt" &&
				name != "causal")
				throw std::runtime_error(j.path + ": unknown estimator '" + name + "'");
		}
	std::vector<MergedRow> out;
	auto take = [&](const std::string& name, const ordered_json* combo) {
		for (std::size_t k = 0; k < jobs.size(); k++)
		{
			const auto& rows = jobs[k].json.at("estimators");
			for (std::size_t i = 0; i < rows.size(); i++)
			{
				const auto& e = rows[i];
				if (e.at("name") == name && (!combo || (e.at("policy") == (*combo)[0] && e.at("fej") == (*combo)[1])))
					out.push_back({k, i, e});
			}
		}
	};
	take("ekf", nullptr);
	std::vector<ordered_json> combos;  // [policy, fej] in the order first seen
	for (const auto& j : jobs)
		for (const auto& e : j.json.at("estimators"))
		{
			const ordered_json key = ordered_json::array({e.at("policy"), e.at("fej")});
			if (e.at("name") == "window" && std::find(combos.begin(), combos.end(), key) == combos.end())
				combos.push_back(key);
		}
	for (const auto& key : combos) take("window", &key);
	take("batch", nullptr);
	take("batch_alt", nullptr);
	take("causal", nullptr);
	return out;
}

/** A job's ape.csv as its lines (header first), or its ape.txt as one block per estimator (each from
 * its "=== " line); one record per "estimators" entry. Throws std::runtime_error naming the file when
 * the count does not match. */
std::vector<std::string> job_file_records(const JobSummary& job, const std::string& name, bool blocks)
{
	const std::string path = job.dir + "/" + name;
	std::ifstream f = open_input_file(path, std::ios::in, "job output");
	std::vector<std::string> records;
	std::string line;
	while (std::getline(f, line))
	{
		if (!blocks || line.rfind("=== ", 0) == 0 || records.empty())
			records.push_back(line + "\n");
		else
			records.back() += line + "\n";
	}
	const std::size_t expected = job.json.at("estimators").size() + (blocks ? 0 : 1);
	if (records.size() != expected || (blocks && !records.empty() && records.front().rfind("=== ", 0) != 0))
		throw std::runtime_error(path + ": " + std::to_string(records.size()) + " " + (blocks ? "blocks" : "lines") +
								 ", expected " + std::to_string(expected) + " (one per estimator of summary.json)");
	return records;
}

void copy_file(const std::string& from, const std::string& to, std::vector<std::string>& files)
{
	std::error_code ec;
	fs::copy_file(from, to, fs::copy_options::overwrite_existing, ec);
	if (ec) throw std::runtime_error("cannot copy '" + from + "' to '" + to + "': " + ec.message());
	files.push_back(to);
}

/** APE rmse per estimator over the rawlogs (several rawlogs only). */
struct AcrossRawlogs
{
	std::vector<std::string> labels;
	std::map<std::string, std::vector<double>> trans_rmse;
	std::map<std::string, std::size_t> failed;
};

std::string format_across_text(const AcrossRawlogs& a, std::size_t rawlogs)
{
	std::size_t wl = std::string("estimator").size();
	for (const auto& l : a.labels) wl = std::max(wl, l.size());
	std::ostringstream s;
	char buf[160];
	s << "APE translation rmse (m) over " << rawlogs << " rawlogs (not aligned)\n";
	std::snprintf(buf, sizeof(buf), "%-*s %6s %6s %11s %11s %11s %11s\n", static_cast<int>(wl), "estimator", "runs",
				  "failed", "mean", "median", "min", "max");
	s << buf << std::string(wl + 62, '-') << "\n";
	for (const auto& l : a.labels)
	{
		const auto& v = a.trans_rmse.at(l);
		if (v.empty())
		{
			std::snprintf(buf, sizeof(buf), "%-*s %6zu %6zu %11s %11s %11s %11s\n", static_cast<int>(wl), l.c_str(),
						  v.size(), a.failed.at(l), "-", "-", "-", "-");
			s << buf;
			continue;
		}
		const eval::Statistics st = eval::compute_statistics(v);
		std::snprintf(buf, sizeof(buf), "%-*s %6zu %6zu %11.6f %11.6f %11.6f %11.6f\n", static_cast<int>(wl), l.c_str(),
					  v.size(), a.failed.at(l), st.mean, st.median, st.min, st.max);
		s << buf;
	}
	return s.str();
}

std::string format_across_csv(const AcrossRawlogs& a)
{
	std::ostringstream s;
	s << "label,runs,failed,trans_rmse_mean,trans_rmse_median,trans_rmse_min,trans_rmse_max\n";
	char buf[200];
	for (const auto& l : a.labels)
	{
		const auto& v = a.trans_rmse.at(l);
		s << eval::csv_field(l) << "," << v.size() << "," << a.failed.at(l);
		if (v.empty())
			s << ",,,,\n";
		else
		{
			const eval::Statistics st = eval::compute_statistics(v);
			std::snprintf(buf, sizeof(buf), ",%.9g,%.9g,%.9g,%.9g\n", st.mean, st.median, st.min, st.max);
			s << buf;
		}
	}
	return s.str();
}

/** A rawlog's jobs' summaries, moved out of every job's (read_complete_jobs); throws std::runtime_error
 * when they did not run on the same rawlog. */
std::vector<JobSummary> group_jobs(std::vector<JobSummary>& summaries, const SweepGroup& g)
{
	std::vector<JobSummary> jobs;
	for (std::size_t id : g.jobs) jobs.push_back(std::move(summaries[id - 1]));
	for (const auto& j : jobs)
		for (const char* key : {"steps", "landmarks", "ground_truth"})
			if (j.json.at(key) != jobs.front().json.at(key))
				throw std::runtime_error(j.path + ": " + key + " differs from " + jobs.front().path +
										 "'s: the jobs did not run on the same rawlog");
	return jobs;
}

/** The merged report's rows (with their association notes), each row's trajectory file, every job's
 * covariance files and the ground truth copied into `dir`. */
void merge_rows_and_copy_files(const std::vector<JobSummary>& jobs, const std::vector<MergedRow>& rows,
							   const std::string& dir, RunReport& report, std::vector<std::string>& files)
{
	for (const auto& m : rows)
	{
		const JobSummary& j = jobs[m.job];
		report.rows.push_back(run_row_from_json(m.entry, j.dir, j.path));
		const RunRow& row = report.rows.back();
		if (row.association && row.trajectory != "lagged") report.notes.push_back(format_association_note(row));
		if (row.file.empty() || !fs::exists(j.dir + "/" + row.file)) continue;
		copy_file(j.dir + "/" + row.file, dir + "/" + row.file, files);
	}
	// Covariance files (<stem>.cov and whatever else swba run writes as *.cov): the jobs' rows have
	// distinct stems, so every job's are copied as they are.
	for (const auto& j : jobs)
		for (const auto& entry : fs::directory_iterator(j.dir))
			if (entry.is_regular_file() && entry.path().extension() == ".cov")
				copy_file(entry.path().string(), dir + "/" + entry.path().filename().string(), files);
	if (fs::exists(jobs.front().dir + "/gt.tum")) copy_file(jobs.front().dir + "/gt.tum", dir + "/gt.tum", files);
}

/** ape.txt and ape.csv: the jobs' own records, in the merged order (every column they have, verbatim). */
std::pair<std::string, std::string> merged_ape_text_and_csv(const std::vector<JobSummary>& jobs,
															 const std::vector<MergedRow>& rows)
{
	std::vector<std::vector<std::string>> csv, text;
	for (const auto& j : jobs)
	{
		csv.push_back(job_file_records(j, "ape.csv", false));
		text.push_back(job_file_records(j, "ape.txt", true));
	}
	std::string merged_csv = csv.front().front(), merged_text;
	for (const auto& m : rows)
	{
		merged_csv += csv[m.job][m.index + 1];
		merged_text += text[m.job][m.index];
	}
	return {merged_text, merged_csv};
}

/** The plots swba run draws, from the merged rows (as swba run: without gnuplot their data and scripts
 * are written all the same). */
void draw_merged_plots(const RunOptions& run, const std::string& dir, RunReport& report,
					   std::vector<std::string>& files)
{
	if (eval::find_gnuplot().empty())
		report.notes.push_back("gnuplot not found: plots not drawn; their data (.dat) and scripts (.gp) are in " + dir +
							   "/ and " + dir + "/plots/ (cd there && gnuplot <name>.gp)");
	std::vector<mrpt::poses::CPose3D> gt;
	if (!report.ground_truth.empty()) gt = eval::read_ground_truth_for(report.ground_truth, report.steps);
	for (auto& r : report.rows)
		if (r.has_ape && !r.estimate.empty())
			r.ape_trans_errors = eval::ape_errors_against_ground_truth(gt, r.estimate, eval::PoseRelation::TranslationPart);
	report.files.clear();
	write_run_plots(run, gt, report);
	files.insert(files.end(), report.files.begin(), report.files.end());
}

/** An inertial rawlog: its one job's outputs copied into `dir` as they are; `table` is its ape.txt and
 * the report's rows carry the labels and APE of its summary.json (for the table across rawlogs). */
RunReport merge_inertial_group(const JobSummary& job, const std::string& dir, std::string& table,
							   std::vector<std::string>& files)
{
	const std::string& job_dir = job.dir;
	std::error_code ec;
	fs::create_directories(dir, ec);
	if (ec) throw std::runtime_error("cannot create '" + dir + "': " + ec.message());
	for (const auto& entry : fs::directory_iterator(job_dir))
		if (entry.is_regular_file()) copy_file(entry.path().string(), dir + "/" + entry.path().filename().string(), files);
	table = read_text_file(job_dir + "/ape.txt", "job output");
	const ordered_json& j = job.json;
	RunReport report;
	report.rawlog = j.at("rawlog").get<std::string>();
	for (const auto& e : j.at("rows"))
	{
		RunRow row;
		row.label = e.at("label").get<std::string>();
		row.has_ape = e.contains("ape_trans");
		if (row.has_ape) row.ape_trans.rmse = e.at("ape_trans").at("rmse").get<double>();
		report.rows.push_back(row);
	}
	return report;
}

/** One rawlog: its jobs merged into `dir`. */
RunReport merge_group(const SweepPlan& plan, const std::vector<JobSummary>& jobs, const RunOptions& config,
					  const std::string& dir, const MergeOptions& options, std::vector<std::string>& files)
{
	ordered_json merged = jobs.front().json;
	const auto rows = merged_estimators(jobs);
	merged["estimators"] = ordered_json::array();
	for (const auto& r : rows) merged["estimators"].push_back(r.entry);

	std::error_code ec;
	fs::create_directories(dir, ec);
	if (ec) throw std::runtime_error("cannot create '" + dir + "': " + ec.message());
	RunReport report;
	report.rawlog = merged.at("rawlog").get<std::string>();
	report.ground_truth = merged.at("ground_truth").is_null() ? "" : merged.at("ground_truth").get<std::string>();
	report.steps = merged.at("steps").get<std::size_t>();
	report.distinct_landmarks = merged.at("landmarks").get<std::size_t>();
	merge_rows_and_copy_files(jobs, rows, dir, report, files);

	RunOptions run = config;
	run.out_dir = dir;
	run.rawlog = report.rawlog;
	run.ground_truth = report.ground_truth;
	run.windows = plan.windows;
	run.plots = options.plots;
	auto write = [&](const std::string& name, const std::string& text) {
		write_text_file_atomically(dir + "/" + name, text);
		files.push_back(dir + "/" + name);
	};
	const auto [ape_text, ape_csv] = merged_ape_text_and_csv(jobs, rows);
	write("ape.txt", ape_text);
	write("ape.csv", ape_csv);
	write("summary.json", merged.dump(2, ' ', false, ordered_json::error_handler_t::replace) + "\n");
	write("config.ini", "# swba run: the options of this run (load with --config)\n" + format_run_config(run));
	if (options.plots) draw_merged_plots(run, dir, report, files);
	return report;
}
}  // namespace

RunMerge merge_run_sweep(const SweepPlan& plan, const MergeOptions& options, std::ostream& out, std::ostream& log)
{
	std::vector<JobSummary> summaries = check_mergeable(plan, SweepKind::Run, "run", log);
	RunOptions config;
	load_run_config(plan.dir + "/config.ini", config);
	const std::string out_dir = options.out_dir.empty() ? plan.dir + "/merged" : options.out_dir;
	RunMerge result;
	AcrossRawlogs across;
	for (const auto& g : plan.groups)
	{
		const std::string dir = out_dir + "/" + g.name;
		std::string table;
		RunReport report = g.inertial
							   ? merge_inertial_group(summaries[g.jobs.front() - 1], dir, table, result.files)
							   : merge_group(plan, group_jobs(summaries, g), config, dir, options, result.files);
		out << (g.inertial ? table : format_comparison_table(report)) << "\n" << std::flush;
		for (const auto& note : report.notes) log << "note: " << g.name << ": " << note << "\n";
		for (const auto& r : report.rows)
		{
			if (!across.trans_rmse.count(r.label))
			{
				across.labels.push_back(r.label);
				across.trans_rmse[r.label] = {};
				across.failed[r.label] = 0;
			}
			if (r.has_ape)
				across.trans_rmse[r.label].push_back(r.ape_trans.rmse);
			else if (r.failed)
				across.failed[r.label]++;
		}
		log << "swba merge: " << g.name << ": " << g.jobs.size() << " jobs merged into " << dir << "/\n";
		result.reports.push_back(std::move(report));
	}
	if (plan.groups.size() > 1)
	{
		const std::string text = format_across_text(across, plan.groups.size());
		out << text << std::flush;
		for (const auto& [name, content] : {std::make_pair("ape_across_rawlogs.txt", text),
											std::make_pair("ape_across_rawlogs.csv", format_across_csv(across))})
		{
			write_text_file_atomically(out_dir + "/" + name, content);
			result.files.push_back(out_dir + "/" + name);
		}
	}
	log << "swba merge: merged files in " << out_dir << "/\n";  // (no file count: it follows what swba run writes)
	return result;
}
}  // namespace swba::apps
