/** \file compare.h
 * `swba compare`: two sets of `swba run` results (run directories, sweeps, merged sweeps) paired by
 * rawlog and estimator, as the ratio of one figure (APE translation rmse by default).
 *
 * Why paired ratios: when one early decision moves a run by a factor of two, a difference between two
 * configurations on a few rawlogs says little; the mean over many rawlogs of log(other / base), with its
 * standard error, says whether a change helps beyond that scatter, and a ratio treats a log where every
 * estimator is poor the same as one where all are good. */
#pragma once

#include <swba/core/names.h>

#include <array>
#include <cstddef>
#include <iosfwd>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace swba::apps
{
/** The figure compared: the rmse of one of the error statistics summary.json holds. */
enum class CompareMetric
{
	ApeTrans,  ///< APE translation rmse (m): "ape_trans"
	ApeRot,    ///< APE rotation angle rmse (deg): "ape_rot" ("ape_rot_deg" in an inertial summary)
	RpeTrans   ///< RPE translation rmse (m) between consecutive steps: "rpe_trans"
};
constexpr std::array<EnumName<CompareMetric>, 3> enum_names(CompareMetric)
{
	return {{{CompareMetric::ApeTrans, "ape_trans"}, {CompareMetric::ApeRot, "ape_rot"}, {CompareMetric::RpeTrans, "rpe_trans"}}};
}

/** One row's figure in one summary.json: a finite value, or why there is none. */
struct ResultFigure
{
	std::optional<double> value;  ///< empty when the row failed, diverged, was interrupted or has no figure
	std::string status;           ///< "" with a value; else "failed", "diverged", "interrupted" or "no figure"
	std::string source;           ///< the summary.json it was read from
};

/** Every row of every summary.json found below some paths: figures[rawlog][row], a row named by its label
 * (a batch row's without its start: "batch (DR start)" is "batch"). */
struct ResultSet
{
	std::map<std::string, std::map<std::string, ResultFigure>> figures;
	std::vector<std::string> labels;  ///< rows in the order of the summary with the most rows, then the others
	std::size_t summaries = 0;        ///< summary.json files read
};

/** Reads `path` (a summary.json, or a directory searched recursively for them; a sweep's jobs and its
 * merge hold the same figures) into a ResultSet keyed by the rawlog as each summary names it and by
 * the row's label. Throws std::runtime_error naming the file on an unreadable or malformed summary,
 * when `path` holds none, and when two summaries give one rawlog and row different figures. */
ResultSet read_results(const std::string& path, CompareMetric metric);

/** One estimator (row label) compared over the rawlogs both sides have. */
struct PairedComparison
{
	std::string label;
	std::vector<std::string> rawlogs;  ///< paired, both finite, sorted
	std::vector<double> base, other;   ///< their figures
	double base_geomean = 0, other_geomean = 0;
	double mean_log_ratio = 0;                  ///< mean of ln(other / base)
	std::optional<double> log_ratio_std_error;  ///< its standard error (sample sd / √n), n ≥ 2
	std::size_t better = 0, worse = 0, equal = 0;  ///< other < base, other > base, identical
	std::size_t no_figure_base = 0, no_figure_other = 0;  ///< rawlogs in both where only that side has no figure
	std::size_t no_figure_both = 0;
};

/** The paired comparison of `label` (empty rawlogs when none is paired). */
PairedComparison compare_label(const ResultSet& base, const ResultSet& other, const std::string& label);

struct CompareOptions
{
	std::string base, other;  ///< paths read by read_results
	CompareMetric metric = CompareMetric::ApeTrans;
	bool per_rawlog = false;  ///< also print each rawlog's pair
	std::string json_path;    ///< "" = none; else the comparison as JSON
};

/** `swba compare`: the table on `out`, notes (rawlogs or rows on one side only, figures missing) on
 * `log`. Returns 0; throws std::runtime_error as read_results, or when no rawlog and row is in both. */
int run_compare(const CompareOptions& options, std::ostream& out, std::ostream& log);
}  // namespace swba::apps
