/** \file decoder_probe.h
 * Decoding an untrusted rawlog once in a child process, so that MRPT's deserialisation cannot take the
 * reading process down with it (private to swba::io). */
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

namespace swba::io::detail
{
/** Where and how the decoder died in the probe. */
struct DecoderDeath
{
	std::size_t entry = 0;  ///< the entry (object) being decoded
	std::string how;        ///< e.g. "killed by signal 11 (Segmentation fault)", "ended with exit status 1 (…)"
};

/** Decodes the first `max_entries` objects (default: all) of the MRPT serialised stream `path` (plain
 * or gzip) in a forked child whose data segment is capped at its size plus `budget_bytes` (RLIMIT_DATA:
 * it covers malloc's heap and anonymous mappings, and it works under AddressSanitizer, whose allocator
 * then fails and exits; 0 = no cap), with its standard output and error discarded. Returns nothing when the child ended normally —
 * at the end of the data or at any exception, which the caller's own reading meets again and reports
 * — and the entry and the cause when it died (a signal, or a non-zero exit such as a sanitizer's report).
 * Nothing, too, when the child's status cannot be known (an application that ignores SIGCHLD).
 *
 * Why: MRPT 2.5's decoder dereferences null objects read from the file (e.g. a CActionRobotMovement2D
 * whose pose PDF is stored as "nullptr") and allocates whatever a corrupt length asks for; neither can
 * be caught in-process. Throws std::runtime_error when the child cannot be started. */
std::optional<DecoderDeath> probe_decoder_in_child(const std::string& path, std::uint64_t budget_bytes,
												   std::uint64_t max_entries = ~std::uint64_t(0));
}  // namespace swba::io::detail
