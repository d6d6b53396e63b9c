// Rawlogs whose length or count fields ask MRPT's decoder for gigabytes (the fuzzer's reproducers in
// fuzz/findings/mrpt/): read_rawlog's memory budget turns each into a one-line error naming the entry,
// quickly and with the process's peak memory far below 1 GB.
#include <swba/core/memory_budget.h>
#include <swba/io/rawlog.h>

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
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

TEST(RawlogMemoryBudget, CorruptLengthFieldsAreAnErrorNotAnAllocation)
{
	if (!swba::ScopedMemoryBudget::supported()) GTEST_SKIP() << "no address-space budget in sanitizer builds";
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
			swba::io::read_rawlog(e.path().string());
			ADD_FAILURE() << "read without an error";
		}
		catch (const std::runtime_error& err)
		{
			const std::string what = err.what();
			EXPECT_NE(what.find("memory budget of 256 MiB"), std::string::npos) << what;
			EXPECT_EQ(what.find('\n'), std::string::npos) << what;
		}
		EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 10.0);
	}
	EXPECT_EQ(files, 5);
	rusage usage{};
	ASSERT_EQ(getrusage(RUSAGE_SELF, &usage), 0);
	EXPECT_LT(usage.ru_maxrss, 1024 * 1024) << "peak RSS in KiB";  // < 1 GiB
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
