// A fresh temporary directory named after the running test, and a file's content (tests/apps).
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

inline std::filesystem::path temp_dir()
{
	const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
	std::filesystem::path d = std::filesystem::temp_directory_path() /
		(std::string("swba_runapp_") + info->test_suite_name() + "_" + info->name());
	std::filesystem::remove_all(d);
	std::filesystem::create_directories(d);
	return d;
}

/** The whole content of file `p` ("" if it cannot be read). */
inline std::string slurp(const std::filesystem::path& p)
{
	std::ifstream f(p);
	std::stringstream ss;
	ss << f.rdbuf();
	return ss.str();
}
