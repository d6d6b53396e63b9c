// swba run's output directory: created and checked before any estimator runs, cleared of an earlier
// run's files, and a manifest of what this run wrote (internal to the run app; see doc/run.md).
#pragma once

#include <ostream>
#include <string>
#include <vector>

namespace swba::apps
{
/** The manifest's name inside the output directory: one file a line, relative to the directory. */
inline constexpr const char* kRunManifest = "swba_run_files.txt";

/** Creates `dir` and checks that a file can be created in it (a run must not spend its estimation
 * time and then lose the results to a mistyped or read-only --out); then removes the files an
 * earlier run listed in `dir`'s manifest, so that the directory never mixes two runs. Says on `log`
 * how many files were removed and how many other files (not written by swba run) are kept. Throws
 * std::runtime_error naming the directory when it cannot be created or written. */
void prepare_output_directory(const std::string& dir, const std::string& program, std::ostream& log);

/** Writes `dir`'s manifest: the paths of `files` that lie inside `dir`, relative to it, each once. */
void write_run_manifest(const std::string& dir, const std::vector<std::string>& files);
}  // namespace swba::apps
