#pragma once
// What a gzip-compressed file holds, found by inflating it once: how many members, how many bytes
// they decompress to, whether the last one is complete, and what follows the last member.
//
// zlib's gzread (behind MRPT's CFileGZInputStream) reads concatenated members as one stream, ignores
// bytes after the last member that do not start another one, and reports a stream cut between two
// deflate blocks as a clean end of file. A reader that stops cleanly on an object boundary therefore
// cannot tell a cut file from a whole one by itself: it compares what it read with this scan.
#include <cstdint>
#include <string>

namespace swba::io::detail
{
struct GzipScan
{
	bool gzip = false;				   ///< the file starts with the gzip magic bytes
	std::uint64_t members = 0;		   ///< complete members (deflate data, CRC-32 and size checked)
	std::uint64_t data_bytes = 0;	   ///< decompressed bytes, those of an incomplete last member included
	bool truncated = false;			   ///< the file ends inside a member (before its trailer)
	std::string damage;				   ///< zlib's reason when a member does not inflate (bad data, CRC)
	std::uint64_t damage_offset = 0;   ///< compressed offset of the member that does not inflate
	std::uint64_t trailing_bytes = 0;  ///< bytes after the last member that do not start another one
};

/** Scans `path`; for a file that is not gzip-compressed returns {gzip = false} and reads 2 bytes.
 * Throws std::runtime_error (not naming the file: callers do) only when it cannot be opened or read. */
GzipScan scan_gzip(const std::string& path);

/** "" when a reader that reached a clean end after `read_bytes` decompressed bytes has read the whole
 * file; else what is wrong in words, e.g. "the gzip stream ends inside member 2 (before its trailer)".
 * Trailing bytes are not a fault: gzip_trailing_note says them. */
std::string gzip_end_fault(const GzipScan& s, std::uint64_t read_bytes);
/** "" or "N bytes after the last gzip member ignored (not a gzip member)". */
std::string gzip_trailing_note(const GzipScan& s);
}  // namespace swba::io::detail
