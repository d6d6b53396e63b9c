// Input checks and atomic writes (swba/core/file.h).
#include <swba/core/file.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <sstream>
#include <stdexcept>

namespace
{
namespace fs = std::filesystem;

fs::path temp_dir()
{
	const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
	fs::path d = fs::temp_directory_path() / (std::string("swba_file_") + info->name());
	fs::remove_all(d);
	fs::create_directories(d);
	return d;
}

std::string read_all(const fs::path& p)
{
	std::ifstream f(p);
	std::stringstream s;
	s << f.rdbuf();
	return s.str();
}

std::string error_of(const std::function<void()>& f)
{
	try
	{
		f();
	}
	catch (const std::exception& e)
	{
		return e.what();
	}
	return "";
}

TEST(File, CheckInputFileNamesWhatIsWrong)
{
	const auto d = temp_dir();
	std::ofstream(d / "ok.txt") << "x";
	EXPECT_NO_THROW(swba::check_input_file((d / "ok.txt").string()));
	EXPECT_EQ(error_of([&] { swba::check_input_file((d / "none").string(), "rawlog"); }),
			  "rawlog '" + (d / "none").string() + "': file does not exist");
	EXPECT_EQ(error_of([&] { swba::check_input_file(d.string()); }), "'" + d.string() + "': is a directory, not a file");
	EXPECT_EQ(error_of([] { swba::check_input_file("/dev/zero"); }),
			  "'/dev/zero': is not a regular file (a FIFO, device or socket)");
	EXPECT_EQ(error_of([] { swba::check_input_file(""); }), "input: empty file name");
}

TEST(File, AtomicWriteReplacesTheFileOnlyWhenComplete)
{
	const auto d = temp_dir();
	const fs::path p = d / "out.txt";
	swba::write_file_atomically(p.string(), [](std::ostream& f) { f << "first\n"; });
	EXPECT_EQ(read_all(p), "first\n");
	// A writer that fails half-way leaves the previous file as it was, and no temporary file.
	EXPECT_THROW(swba::write_file_atomically(p.string(),
											 [](std::ostream& f) {
												 f << "half";
												 throw std::runtime_error("interrupted");
											 }),
				 std::runtime_error);
	EXPECT_EQ(read_all(p), "first\n");
	EXPECT_EQ(std::distance(fs::directory_iterator(d), fs::directory_iterator{}), 1);
	swba::write_file_atomically(p.string(), [](std::ostream& f) { f << "second\n"; });
	EXPECT_EQ(read_all(p), "second\n");
}

TEST(File, AtomicWriteNamesTheFileAndTheOsReason)
{
	const auto d = temp_dir();
	const std::string missing_dir = (d / "no_such_dir" / "x.txt").string();
	EXPECT_EQ(error_of([&] { swba::write_file_atomically(missing_dir, [](std::ostream& f) { f << "x"; }); }),
			  "cannot write '" + missing_dir + "': No such file or directory");
	// A full device: written in place (never renamed over), the error surfaces at flush.
	if (fs::exists("/dev/full"))
	{
		EXPECT_EQ(error_of([] {
					  swba::write_file_atomically("/dev/full", [](std::ostream& f) { f << std::string(1 << 16, 'x'); });
				  }),
				  "cannot write '/dev/full': No space left on device");
	}
	EXPECT_TRUE(fs::is_character_file("/dev/full"));
}
}  // namespace
