/** \file fuzz_common.h
 * Shared pieces of the reader harnesses (fuzz_<reader>.cpp). Each harness defines
 * LLVMFuzzerTestOneInput and returns 0 for every input a reader handles: a parsed result or a
 * std::exception (the documented way a reader rejects bad input). Anything else — a crash, a
 * sanitizer report, a non-std exception escaping (std::terminate), a leak, an allocation beyond
 * libFuzzer's limits, a hang — is a finding. The same entry points are linked into ordinary
 * executables with replay_main.cpp, so the committed corpora also run in the normal test suite. */
#pragma once

#include <cstddef>
#include <cstdint>
#include <exception>
#include <string>

namespace swba::fuzz
{
/** The input bytes as a string (readers taking text). */
inline std::string as_text(const uint8_t* data, size_t size)
{
	return std::string(reinterpret_cast<const char*>(data), size);
}

/** Called by the harnesses for a std::exception, the expected way to reject an input: prints what()
 * to stderr when the environment variable SWBA_FUZZ_VERBOSE is set (to see why a seed or regression
 * is rejected), else nothing, so that libFuzzer's output stays readable. Except std::bad_alloc, which
 * aborts: a reader's memory must stay proportional to its input, and the replay driver caps the
 * address space so that a reintroduced unbounded allocation fails there instead of swapping. */
void rejected(const std::exception& e);

/** The body of every harness: runs `read` (the reader on this input) and hands a std::exception it
 * throws to rejected(). Anything else it throws escapes, a finding. */
template <class Read>
void read_or_reject(Read&& read)
{
	try
	{
		read();
	}
	catch (const std::exception& e)
	{
		rejected(e);
	}
}

/** A directory private to this process, /tmp/swba_fuzz_<pid>/, created on first use, for readers
 * that only take a path. Files in it are overwritten by each input; libFuzzer runs one input at a
 * time per process, so no locking is needed. The directory is removed at exit. */
const std::string& scratch_dir();

/** Writes `bytes` to `scratch_dir()/name` (truncating) and returns the path. Aborts if the file
 * cannot be written: a broken harness must not pass for a reader that rejected its input. */
std::string write_scratch_file(const std::string& name, const std::string& bytes);

/** Removes `scratch_dir()/name` if present (a file left by the previous input must not leak into
 * the next one). */
void remove_scratch_file(const std::string& name);
}  // namespace swba::fuzz
