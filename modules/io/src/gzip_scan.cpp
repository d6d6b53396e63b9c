#include "gzip_scan.h"

#include <zlib.h>

#include <fstream>
#include <stdexcept>
#include <vector>

namespace swba::io::detail
{
namespace
{
/** One inflate stream that decodes gzip members one after the other (windowBits 16 + 15: gzip
 * wrapper, CRC-32 and ISIZE checked by zlib). */
class MemberInflater
{
public:
	MemberInflater()
	{
		if (inflateInit2(&z_, 16 + MAX_WBITS) != Z_OK) throw std::runtime_error("zlib: inflateInit2 failed");
	}
	~MemberInflater() { inflateEnd(&z_); }
	MemberInflater(const MemberInflater&) = delete;
	MemberInflater& operator=(const MemberInflater&) = delete;

	z_stream& stream() { return z_; }
	void next_member() { inflateReset(&z_); }

private:
	z_stream z_{};
};

bool starts_member(const unsigned char* p, std::size_t n) { return n >= 2 && p[0] == 0x1f && p[1] == 0x8b; }
}  // namespace

GzipScan scan_gzip(const std::string& path)
{
	std::ifstream f(path, std::ios::binary);
	if (!f) throw std::runtime_error("cannot open the file for reading");
	GzipScan s;
	std::vector<unsigned char> in(1 << 16), out(1 << 18);
	f.read(reinterpret_cast<char*>(in.data()), 2);
	if (f.gcount() < 2 || !starts_member(in.data(), 2)) return s;
	s.gzip = true;
	f.seekg(0);
	MemberInflater inflater;
	z_stream& z = inflater.stream();
	std::uint64_t consumed = 0;		 // compressed bytes given to zlib and used by it
	std::uint64_t member_start = 0;	 // compressed offset of the member being inflated
	bool in_member = true;			 // between members: the next bytes decide member or trailing bytes
	for (;;)
	{
		if (z.avail_in == 0)
		{
			f.read(reinterpret_cast<char*>(in.data()), std::streamsize(in.size()));
			if (f.bad()) throw std::runtime_error("read error while scanning its gzip members");
			z.next_in = in.data();
			z.avail_in = static_cast<uInt>(f.gcount());
			if (z.avail_in == 0) break;	 // end of file
		}
		if (!in_member)
		{
			// zlib's gzread: another member only if the next two bytes are the magic ones.
			if (z.avail_in < 2 && f.peek() != std::char_traits<char>::eof())
			{
				in[0] = *z.next_in;
				f.read(reinterpret_cast<char*>(in.data() + 1), std::streamsize(in.size() - 1));
				z.next_in = in.data();
				z.avail_in = static_cast<uInt>(f.gcount()) + 1;
			}
			if (!starts_member(z.next_in, z.avail_in))
			{
				f.clear();
				f.seekg(0, std::ios::end);
				s.trailing_bytes = static_cast<std::uint64_t>(f.tellg()) - consumed;
				return s;
			}
			inflater.next_member();
			member_start = consumed;
			in_member = true;
		}
		z.next_out = out.data();
		z.avail_out = static_cast<uInt>(out.size());
		const uInt had = z.avail_in;
		const int rc = inflate(&z, Z_NO_FLUSH);
		consumed += had - z.avail_in;
		s.data_bytes += out.size() - z.avail_out;
		if (rc == Z_STREAM_END)
		{
			s.members++;
			in_member = false;
		}
		else if (rc != Z_OK && rc != Z_BUF_ERROR)
		{
			s.damage = z.msg ? z.msg : "zlib error " + std::to_string(rc);
			s.damage_offset = member_start;
			return s;
		}
	}
	s.truncated = in_member;
	return s;
}

std::string gzip_end_fault(const GzipScan& s, std::uint64_t read_bytes)
{
	if (!s.gzip) return "";
	const std::string member = "member " + std::to_string(s.members + 1);
	if (!s.damage.empty())
		return "gzip " + member + " (at byte " + std::to_string(s.damage_offset) + ") does not decompress: " + s.damage;
	if (s.truncated) return "the gzip stream ends inside " + member + " (before its trailer)";
	if (read_bytes != s.data_bytes)
		return std::to_string(read_bytes) + " of the " + std::to_string(s.data_bytes) + " decompressed bytes read";
	return "";
}

std::string gzip_trailing_note(const GzipScan& s)
{
	if (s.trailing_bytes == 0) return "";
	return std::to_string(s.trailing_bytes) + (s.trailing_bytes == 1 ? " byte" : " bytes") +
		" after the last gzip member ignored (not a gzip member)";
}
}  // namespace swba::io::detail
