// Rawlogs whose length or count fields ask MRPT's decoder for gigabytes (the fuzzer's reproducers in
// fuzz/findings/mrpt/): read_rawlog's memory budget turns each into a one-line error naming the entry,
// quickly and with the process's peak memory far below 1 GB; objects MRPT's decoder crashes on end the
// reading the same way (the decoder probe).
#include <swba/io/observation_rawlog.h>
#include <swba/io/rawlog.h>

#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>

#include <sys/resource.h>

namespace
{
namespace fs = std::filesystem;

TEST(RawlogMemoryBudget, AutoBudgetIsBaseAndSixteenTimesTheData)
{
	EXPECT_EQ(swba::io::auto_memory_budget(0), std::uint64_t(256) << 20);
	EXPECT_EQ(swba::io::auto_memory_budget(1000), (std::uint64_t(256) << 20) + 16000);
	EXPECT_GT(swba::io::auto_memory_budget(~std::uint64_t(0) / 2), std::uint64_t(1) << 62);  // no overflow
}

/** Runs `read` on each reproducer of fuzz/findings/mrpt/ (it must throw std::runtime_error, whose
 * one-line text goes to `check`), each in under 10 s, with this process's and its probes' peak
 * resident memory below 1 GiB. */
void expect_each_reproducer_rejected(const std::function<void(const std::string&)>& read,
									 const std::function<void(const std::string&)>& check)
{
	const fs::path dir = fs::path(SWBA_SHARE_DIR) / ".." / "fuzz" / "findings" / "mrpt";
	int files = 0;
	for (const auto& e : fs::directory_iterator(dir))
	{
		if (e.path().extension() != ".rawlog") continue;
		files++;
		SCOPED_TRACE(e.path().filename().string());
		const auto start = std::chrono::steady_clock::now();
		try
		{
			read(e.path().string());
			ADD_FAILURE() << "read without an error";
		}
		catch (const std::runtime_error& err)
		{
			check(err.what());
			EXPECT_EQ(std::string(err.what()).find('\n'), std::string::npos) << err.what();
		}
		EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 10.0);
	}
	EXPECT_EQ(files, 5);
	rusage usage{};
	ASSERT_EQ(getrusage(RUSAGE_SELF, &usage), 0);
	EXPECT_LT(usage.ru_maxrss, 1024 * 1024) << "peak RSS in KiB";  // < 1 GiB
	ASSERT_EQ(getrusage(RUSAGE_CHILDREN, &usage), 0);
	EXPECT_LT(usage.ru_maxrss, 1024 * 1024) << "the decoder probes' peak RSS in KiB";
}

TEST(RawlogMemoryBudget, CorruptLengthFieldsAreAnErrorNotAnAllocation)
{
	// In sanitizer builds (no address-space cap in the process) the decoder probe's capped child meets
	// the allocation instead; either way the message names the budget.
	expect_each_reproducer_rejected([](const std::string& path) { swba::io::read_rawlog(path); },
									[](const std::string& what)
									{ EXPECT_NE(what.find("memory budget of 256 MiB"), std::string::npos) << what; });
}

TEST(RawlogMemoryBudget, TheObservationReaderAndTheKindTestReadUnderTheBudgetToo)
{
	// `swba run` first asks is_observation_rawlog, which decodes the first object: unguarded, the
	// 82-byte sensory-frame reproducer took 24 GB of resident memory there before the kernel killed it.
	expect_each_reproducer_rejected(
		[](const std::string& path)
		{
			EXPECT_FALSE(swba::io::is_observation_rawlog(path));
			swba::io::read_observation_rawlog(path);
		},
		[](const std::string& what) { EXPECT_NE(what.find("entry "), std::string::npos) << what; });
}

TEST(RawlogDecoderProbe, AnObjectMrptsDecoderCrashesOnIsACorruptEntryNotACrash)
{
	// A CActionRobotMovement2D whose pose PDF is stored as a null object: MRPT 2.5 dereferences it
	// (SIGSEGV inside libmrpt-obs). Found by the rawlog fuzzing campaign.
	const fs::path file =
		fs::path(SWBA_SHARE_DIR) / ".." / "fuzz" / "regressions" / "rawlog" / "mrpt-null-pose-pdf-segv.rawlog";
	ASSERT_TRUE(fs::exists(file));
	try
	{
		swba::io::read_rawlog(file.string());
		ADD_FAILURE() << "read without an error";
	}
	catch (const std::runtime_error& err)
	{
		const std::string what = err.what();
		EXPECT_NE(what.find("corrupt at entry 1 after 0 complete steps: MRPT's decoder does not survive this object"),
				  std::string::npos)
			<< what;
		EXPECT_EQ(what.find('\n'), std::string::npos) << what;
	}
	swba::io::RawlogReaderOptions lenient;
	lenient.allow_truncated = true;
	try
	{
		swba::io::read_rawlog(file.string(), lenient);  // keeps the steps before the damage: none here
		ADD_FAILURE() << "read without an error";
	}
	catch (const std::runtime_error& err)
	{
		EXPECT_NE(std::string(err.what()).find("no action/sensory-frame pairs"), std::string::npos) << err.what();
	}
}

TEST(RawlogDecoderProbe, ANormalRawlogReadsTheSameWithAndWithoutTheProbe)
{
	swba::io::RawlogReaderOptions unprobed;
	unprobed.probe_decoder = false;
	const std::string demo = std::string(SWBA_MRPT_DATASETS) + "/kf-slam_6D_demo.rawlog";
	const auto probed = swba::io::read_rawlog(demo);
	const auto plain = swba::io::read_rawlog(demo, unprobed);
	EXPECT_EQ(probed.entries, plain.entries);
	EXPECT_EQ(probed.steps.size(), plain.steps.size());
	EXPECT_EQ(probed.readings, plain.readings);
}

TEST(RawlogDecoderProbe, AnApplicationIgnoringSigchldStillReads)
{
	// With SIGCHLD ignored the kernel reaps the probe itself and waitpid fails with ECHILD.
	const auto previous = std::signal(SIGCHLD, SIG_IGN);
	const std::string demo = std::string(SWBA_MRPT_DATASETS) + "/kf-slam_6D_demo.rawlog";
	std::size_t steps = 0;
	EXPECT_NO_THROW(steps = swba::io::read_rawlog(demo).steps.size());
	std::signal(SIGCHLD, previous);
	EXPECT_EQ(steps, 599u);
}

TEST(RawlogMemoryBudget, ANormalRawlogReadsTheSameWithAndWithoutTheBudget)
{
	swba::io::RawlogReaderOptions options;
	options.memory_budget = 0;
	// A normal rawlog reads the same with and without the cap.
	const std::string demo = std::string(SWBA_MRPT_DATASETS) + "/kf-slam_6D_demo.rawlog";
	const auto capped = swba::io::read_rawlog(demo);
	const auto uncapped = swba::io::read_rawlog(demo, options);
	EXPECT_EQ(capped.steps.size(), uncapped.steps.size());
	EXPECT_EQ(capped.readings, uncapped.readings);
}
}  // namespace
