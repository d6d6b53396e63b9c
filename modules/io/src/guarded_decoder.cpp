#include "guarded_decoder.h"

#include <swba/io/rawlog.h>

#include <filesystem>
#include <stdexcept>

namespace swba::io::detail
{
namespace
{
/** Bytes of serialised data in the file: its size, or for gzip its decompressed size. */
std::uint64_t data_size(const std::string& path, const GzipScan& gz)
{
	if (gz.gzip) return gz.data_bytes;
	std::error_code ec;
	const auto size = std::filesystem::file_size(path, ec);
	return ec ? 0 : static_cast<std::uint64_t>(size);
}

/** True when an exception text says an allocation failed. */
bool is_allocation_failure(const std::string& what) { return what.find("bad_alloc") != std::string::npos; }
}  // namespace

GuardedDecoder::GuardedDecoder(const std::string& path, std::uint64_t budget_bytes, bool probe,
							   std::uint64_t probe_entries)
	: gz_(scan_gzip(path)),
	  budget_bytes_(budget_bytes == RawlogReaderOptions::kAutoMemoryBudget ? auto_memory_budget(data_size(path, gz_))
																		   : budget_bytes)
{
	if (probe) death_ = probe_decoder_in_child(path, budget_bytes_, probe_entries);
	std::string error;
	if (!file_.open(path, error)) throw std::runtime_error("cannot open: " + error);
	archive_ = mrpt::serialization::archiveUniquePtrFrom(file_);
}

std::string GuardedDecoder::budget_exceeded() const
{
	if (!(budget_ && budget_->active())) return "out of memory while decoding the object";
	return "the object declares more data than the reading's memory budget of " + std::to_string(budget_bytes_ >> 20) +
		" MiB allows (a corrupt length or count field: MRPT's decoder allocates what the file declares)";
}

std::string GuardedDecoder::next(std::size_t entry, mrpt::serialization::CSerializable::Ptr& obj, bool& clean_end)
{
	if (!started_ && budget_bytes_ > 0) budget_.emplace(budget_bytes_);
	started_ = true;
	if (death_ && death_->entry == entry)
		return "MRPT's decoder does not survive this object: its probe process, decoding it " +
			(budget_bytes_ > 0 ? "under the reading's memory budget of " + std::to_string(budget_bytes_ >> 20) + " MiB"
							   : std::string("with no memory budget")) +
			", was " + death_->how;
	std::string damage;
	const uint64_t pos_before = file_.getPosition();
	try
	{
		*archive_ >> obj;
	}
	catch (const mrpt::serialization::CExceptionEOF& e)
	{
		clean_end = file_.getPosition() == pos_before;
		if (!clean_end) damage = "unexpected end of data inside the object (" + mrpt_exception_summary(e.what()) + ")";
	}
	catch (const std::bad_alloc&)
	{
		damage = budget_exceeded();
	}
	catch (const std::exception& e)
	{
		damage = is_allocation_failure(e.what()) ? budget_exceeded() : mrpt_exception_summary(e.what());
	}
	if (damage.empty() && !clean_end && !obj) damage = "null object";
	// gzread hands on what a damaged member decodes to: the scan says why MRPT's decoding failed.
	if (!damage.empty() && !gz_.damage.empty()) damage += "; " + gzip_end_fault(gz_, 0);
	return damage;
}

std::string GuardedDecoder::end_fault() const { return gzip_end_fault(gz_, file_.getPosition()); }
}  // namespace swba::io::detail
