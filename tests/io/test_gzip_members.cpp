// Both rawlog readers on gzip files as other tools make them: concatenated members (MRPT's own
// observation-rawlog writer, pigz/bgzip), bytes after the last member, a stream cut exactly on an
// object boundary (it reads "cleanly" through gzread), and a member whose CRC is wrong.
#include <swba/io/observation_rawlog.h>
#include <swba/io/rawlog.h>

#include <mrpt/io/CMemoryStream.h>
#include <mrpt/serialization/CArchive.h>

#include <gtest/gtest.h>
#include <zlib.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <stdexcept>

namespace
{
namespace fs = std::filesystem;
using swba::io::RawlogReaderOptions;
using swba::io::read_rawlog;

const std::string kDemo = std::string(SWBA_MRPT_DATASETS) + "/kf-slam_6D_demo.rawlog";

std::string read_bytes(const std::string& path)
{
	std::ifstream f(path, std::ios::binary);
	return std::string(std::istreambuf_iterator<char>(f), {});
}

void write_bytes(const std::string& path, const std::string& bytes)
{
	std::ofstream f(path, std::ios::binary);
	f << bytes;
}

/** A per-test file name (ctest runs the tests of this file in parallel processes). */
std::string temp_path(const std::string& stem)
{
	const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
	return (fs::temp_directory_path() / ("swba_test_gzip_" + std::string(info->name()) + "_" + stem + ".rawlog"))
		.string();
}

std::string gunzip(const std::string& path)
{
	gzFile g = gzopen(path.c_str(), "rb");
	EXPECT_NE(g, nullptr) << path;
	std::string out;
	char buf[1 << 16];
	for (int n; g && (n = gzread(g, buf, sizeof buf)) > 0;) out.append(buf, std::size_t(n));
	if (g) gzclose(g);
	return out;
}

/** One gzip member holding `data`; with `cut_after` < data.size(), only the member's start: the
 * deflate stream of its first `cut_after` bytes, flushed to a byte boundary, with no trailer. */
std::string gzip_member(const std::string& data, std::size_t cut_after = std::string::npos)
{
	z_stream z{};
	EXPECT_EQ(deflateInit2(&z, 6, Z_DEFLATED, 16 + MAX_WBITS, 8, Z_DEFAULT_STRATEGY), Z_OK);
	const bool cut = cut_after < data.size();
	const std::size_t n = cut ? cut_after : data.size();
	std::string out(deflateBound(&z, uLong(n)) + 64, '\0');
	z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data.data()));
	z.avail_in = uInt(n);
	z.next_out = reinterpret_cast<Bytef*>(out.data());
	z.avail_out = uInt(out.size());
	EXPECT_EQ(deflate(&z, cut ? Z_FULL_FLUSH : Z_FINISH), cut ? Z_OK : Z_STREAM_END);
	out.resize(z.total_out);
	deflateEnd(&z);
	return out;
}

/** Offsets in the serialised data at which each object ends. */
std::vector<std::size_t> object_ends(const std::string& data)
{
	mrpt::io::CMemoryStream m;
	m.assignMemoryNotOwn(data.data(), data.size());
	auto arch = mrpt::serialization::archiveFrom(m);
	std::vector<std::size_t> ends;
	while (m.getPosition() < data.size())
	{
		arch.ReadObject();
		ends.push_back(std::size_t(m.getPosition()));
	}
	return ends;
}

std::string expect_error(const std::function<void()>& read)
{
	try
	{
		read();
	}
	catch (const std::runtime_error& e)
	{
		return e.what();
	}
	ADD_FAILURE() << "no error";
	return "";
}

TEST(GzipRangeBearing, ConcatenatedMembersReadAsOneStream)
{
	const auto whole = read_rawlog(kDemo);
	const std::string data = gunzip(kDemo);
	ASSERT_GT(data.size(), 200000u);
	const std::string path = temp_path("members");
	write_bytes(path, gzip_member(data.substr(0, 100000)) + gzip_member(data.substr(100000, 77777)) +
						  gzip_member(data.substr(177777)));
	const auto log = read_rawlog(path);
	EXPECT_EQ(log.steps.size(), whole.steps.size());
	EXPECT_EQ(log.readings, whole.readings);
	EXPECT_EQ(log.entries, whole.entries);
	EXPECT_EQ(log.warning_count, 0u);
	EXPECT_FALSE(log.truncated);
}

TEST(GzipRangeBearing, TrailingBytesAreIgnoredWithAWarning)
{
	const auto whole = read_rawlog(kDemo);
	const std::string path = temp_path("trailing");
	write_bytes(path, read_bytes(kDemo) + "GARBAGE");
	const auto log = read_rawlog(path);
	EXPECT_EQ(log.steps.size(), whole.steps.size());
	EXPECT_EQ(log.readings, whole.readings);
	ASSERT_EQ(log.warning_count, 1u);
	EXPECT_NE(log.warnings[0].find("7 bytes after the last gzip member ignored"), std::string::npos) << log.warnings[0];
	EXPECT_FALSE(log.truncated);
}

TEST(GzipRangeBearing, StreamCutOnAnObjectBoundaryIsTruncated)
{
	const std::string data = gunzip(kDemo);
	const auto ends = object_ends(data);
	ASSERT_GT(ends.size(), 1000u);
	const std::size_t cut = ends[601];	// after 602 entries: SF0, then 300 action/frame pairs
	const std::string one = temp_path("one"), two = temp_path("two");
	write_bytes(one, gzip_member(data, cut));
	write_bytes(two, gzip_member(data.substr(0, ends[99])) + gzip_member(data.substr(ends[99]), cut - ends[99]));
	for (const auto& file_member : {std::pair{one, "member 1"}, std::pair{two, "member 2"}})
	{
		const std::string path = file_member.first, member = file_member.second;
		const std::string msg = expect_error([&] { read_rawlog(path); });
		EXPECT_NE(msg.find(path), std::string::npos) << msg;
		EXPECT_NE(msg.find("truncated gzip stream: the gzip stream ends inside " + member), std::string::npos)
			<< msg;
		EXPECT_NE(msg.find("after 602 entries, 300 complete steps"), std::string::npos) << msg;
		RawlogReaderOptions lenient;
		lenient.allow_truncated = true;
		const auto log = read_rawlog(path, lenient);
		EXPECT_TRUE(log.truncated);
		EXPECT_EQ(log.steps.size(), 300u);
	}
}

TEST(GzipRangeBearing, WrongCrcIsAnError)
{
	std::string bytes = read_bytes(kDemo);
	bytes[bytes.size() - 8] = char(bytes[bytes.size() - 8] ^ 0x5a);  // the trailer's CRC-32
	const std::string path = temp_path("crc");
	write_bytes(path, bytes);
	const std::string msg = expect_error([&] { read_rawlog(path); });
	EXPECT_NE(msg.find(path), std::string::npos) << msg;
	EXPECT_NE(msg.find("truncated or corrupt at entry"), std::string::npos) << msg;
	EXPECT_NE(msg.find("gzip member 1 (at byte 0) does not decompress: incorrect data check"), std::string::npos) << msg;
}

/** An observation rawlog of 40 IMU readings and 5 pose priors through swba's writer. */
std::string write_observations(const std::string& stem)
{
	std::vector<mrpt::obs::CObservation::Ptr> objs;
	const double origin = 1.7e9;
	for (int k = 0; k < 40; k++)
	{
		objs.push_back(swba::io::make_imu_observation(origin, 0.01 * k, {0.1, 0.0, 9.81}, {0.0, 0.0, 0.1}, "IMU"));
		if (k % 10 == 0)
			objs.push_back(swba::io::make_pose_observation(origin, 0.01 * k, mrpt::poses::CPose3D(0.01 * k, 0, 0, 0, 0, 0),
														   Eigen::Matrix<double, 6, 6>::Identity() * 1e-4, "POSE"));
	}
	const std::string path = temp_path(stem);
	swba::io::write_observation_rawlog(path, objs);
	return path;
}

TEST(GzipObservations, TrailingBytesAreAWarning)
{
	const std::string path = write_observations("trailing");
	const auto whole = swba::io::read_observation_rawlog(path);
	EXPECT_TRUE(whole.warnings.empty());
	write_bytes(path, read_bytes(path) + std::string(3, '\0'));
	const auto log = swba::io::read_observation_rawlog(path);
	EXPECT_EQ(log.imu.size(), whole.imu.size());
	EXPECT_EQ(log.pose_priors.size(), whole.pose_priors.size());
	ASSERT_EQ(log.warnings.size(), 1u);
	EXPECT_NE(log.warnings[0].find("3 bytes after the last gzip member ignored"), std::string::npos) << log.warnings[0];
}

TEST(GzipObservations, StreamCutOnAnObjectBoundaryIsAnError)
{
	const std::string path = write_observations("cut");
	const std::string data = gunzip(path);
	const auto ends = object_ends(data);
	ASSERT_EQ(ends.size(), 44u);
	write_bytes(path, gzip_member(data, ends[20]));
	const std::string msg = expect_error([&] { swba::io::read_observation_rawlog(path); });
	EXPECT_NE(msg.find(path), std::string::npos) << msg;
	EXPECT_NE(msg.find("truncated gzip stream: the gzip stream ends inside member 1 (before its trailer), after 21 entries"),
			  std::string::npos)
		<< msg;
}
}  // namespace
