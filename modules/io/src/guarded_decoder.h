/** \file guarded_decoder.h
 * Decoding the objects of an untrusted MRPT serialised file (plain or gzip), as both rawlog readers do
 * (private to swba::io). MRPT 2.5's decoder allocates what a corrupt length field declares and
 * dereferences null objects read from the file; the guards, in order: the file's gzip members are
 * scanned (gzip_scan.h), the decoder is probed once in a child process (decoder_probe.h), and the
 * reading runs under a memory budget (swba/core/memory_budget.h), so that each of those failures is
 * an error naming the entry instead of a crash. */
#pragma once

#include "decoder_probe.h"
#include "gzip_scan.h"

#include <swba/core/memory_budget.h>

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/serialization/CArchive.h>

#include <memory>
#include <optional>
#include <string>

namespace swba::io::detail
{
class GuardedDecoder
{
   public:
	/** Scans and opens `path`; `budget_bytes` as RawlogReaderOptions::memory_budget (kAutoMemoryBudget:
	 * auto_memory_budget of the decompressed size; 0: none); `probe`: decode the first `probe_entries`
	 * objects once in a child first (the reading may read more: those are not probed). Throws
	 * std::runtime_error (without the path) when the file cannot be opened or read. */
	GuardedDecoder(const std::string& path, std::uint64_t budget_bytes, bool probe,
				   std::uint64_t probe_entries = ~std::uint64_t(0));

	/** Decodes entry number `entry` (the next one) into `obj`. Returns "" or what is wrong with the
	 * object, with the gzip scan's reason appended when a member is damaged; sets `clean_end` instead
	 * at the end of the data on an object boundary. The memory budget holds from the first call to
	 * release(). */
	std::string next(std::size_t entry, mrpt::serialization::CSerializable::Ptr& obj, bool& clean_end);
	/** Lifts the memory budget (the reading is over). */
	void release() { budget_.reset(); }

	/** After a clean end: "" or what is wrong with the file's end (detail::gzip_end_fault). */
	std::string end_fault() const;
	/** "" or the warning about bytes after the last gzip member. */
	std::string trailing_note() const { return gzip_trailing_note(gz_); }

   private:
	std::string budget_exceeded() const;

	GzipScan gz_;
	std::uint64_t budget_bytes_ = 0;
	std::optional<DecoderDeath> death_;	 ///< where the probe's decoder died, if it did
	mrpt::io::CFileGZInputStream file_;
	std::unique_ptr<mrpt::serialization::CArchive> archive_;
	std::optional<ScopedMemoryBudget> budget_;
	bool started_ = false;
};
}  // namespace swba::io::detail
