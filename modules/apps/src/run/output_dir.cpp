// swba run's output directory: checked before the run, an earlier run's files removed, a manifest of
// this run's files.
#include "output_dir.h"

#include <swba/core/file.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <stdexcept>
#include <unistd.h>

namespace swba::apps
{
namespace
{
namespace fs = std::filesystem;

/** A manifest line names a file inside the directory: relative, without "..". */
bool inside(const fs::path& relative)
{
	if (relative.empty() || relative.is_absolute()) return false;
	for (const auto& part : relative)
		if (part == "..") return false;
	return true;
}

/** Removes the files listed in dir's manifest (and the manifest, and the sub-directories they leave
 * empty); returns how many files were removed. */
std::size_t remove_listed_files(const fs::path& dir)
{
	std::ifstream manifest(dir / kRunManifest);
	if (!manifest) return 0;
	std::size_t removed = 0;
	std::set<fs::path> parents;
	std::error_code ec;
	for (std::string line; std::getline(manifest, line);)
	{
		const fs::path rel(line);
		if (!inside(rel) || !fs::is_regular_file(dir / rel, ec)) continue;
		if (fs::remove(dir / rel, ec)) removed++;
		if (rel.has_parent_path()) parents.insert(rel.parent_path());
	}
	manifest.close();
	fs::remove(dir / kRunManifest, ec);
	for (auto it = parents.rbegin(); it != parents.rend(); ++it)
		if (fs::is_directory(dir / *it, ec) && fs::is_empty(dir / *it, ec)) fs::remove(dir / *it, ec);
	return removed;
}
}  // namespace

void prepare_output_directory(const std::string& dir, const std::string& program, std::ostream& log)
{
	std::error_code ec;
	if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
		throw std::runtime_error("output directory '" + dir + "' exists and is not a directory");
	fs::create_directories(dir, ec);
	if (ec) throw std::runtime_error("cannot create output directory '" + dir + "': " + ec.message());
	const std::string probe = dir + "/.swba_write_test." + std::to_string(::getpid());
	std::FILE* f = std::fopen(probe.c_str(), "w");
	if (!f) throw std::runtime_error("cannot write into output directory '" + dir + "': " + std::strerror(errno));
	std::fclose(f);
	std::remove(probe.c_str());

	const std::size_t removed = remove_listed_files(dir);
	if (removed > 0) log << program << ": removed the " << removed << " files of an earlier run from " << dir << "/\n";
	std::size_t others = 0;
	for (auto it = fs::recursive_directory_iterator(dir, ec); !ec && it != fs::recursive_directory_iterator();
		 it.increment(ec))
		if (it->is_regular_file(ec)) others++;
	if (others > 0)
		log << program << ": warning: " << dir << "/ holds " << others
			<< " files that swba run did not write (or wrote before it kept a list): kept, and may be mixed with "
			   "this run's\n";
}

void write_run_manifest(const std::string& dir, const std::vector<std::string>& files)
{
	std::set<std::string> seen;
	write_file_atomically((fs::path(dir) / kRunManifest).string(), [&](std::ostream& out) {
		for (const auto& f : files)
		{
			const fs::path rel = fs::path(f).lexically_relative(dir);
			if (inside(rel) && seen.insert(rel.string()).second) out << rel.string() << "\n";
		}
	});
}
}  // namespace swba::apps
