// One printable line of an exception text: control bytes and raw file bytes escaped, well-formed UTF-8
// kept when asked (a UTF-8 terminal), and the locale test behind that choice.
#include <swba/io/rawlog.h>

#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

namespace
{
/** Sets LC_ALL, LC_CTYPE and LANG for the lifetime of the object, restoring them after. */
class Locale
{
   public:
	Locale(const char* all, const char* ctype, const char* lang)
	{
		const char* names[3] = {"LC_ALL", "LC_CTYPE", "LANG"};
		const char* values[3] = {all, ctype, lang};
		for (int i = 0; i < 3; i++)
		{
			const char* old = std::getenv(names[i]);
			saved_[i] = {old != nullptr, old ? old : ""};
			if (values[i])
				::setenv(names[i], values[i], 1);
			else
				::unsetenv(names[i]);
		}
	}
	~Locale()
	{
		const char* names[3] = {"LC_ALL", "LC_CTYPE", "LANG"};
		for (int i = 0; i < 3; i++)
			if (saved_[i].first)
				::setenv(names[i], saved_[i].second.c_str(), 1);
			else
				::unsetenv(names[i]);
	}
	Locale(const Locale&) = delete;
	Locale& operator=(const Locale&) = delete;

   private:
	std::pair<bool, std::string> saved_[3];
};
}  // namespace

TEST(ExceptionText, Utf8IsKeptOnlyWhenAskedAndBadBytesAreEscaped)
{
	const std::string ge = "noise must be a number \xe2\x89\xa5 0";
	EXPECT_EQ(swba::io::mrpt_exception_summary(ge, true), ge);
	EXPECT_EQ(swba::io::mrpt_exception_summary(ge, false), "noise must be a number \\xe2\\x89\\xa5 0");
	// Not UTF-8: a lone continuation byte, a truncated sequence, an overlong form, a surrogate, a NUL.
	EXPECT_EQ(swba::io::mrpt_exception_summary(std::string("a\x80z"), true), "a\\x80z");
	EXPECT_EQ(swba::io::mrpt_exception_summary(std::string("a\xe2\x89"), true), "a\\xe2\\x89");
	EXPECT_EQ(swba::io::mrpt_exception_summary(std::string("\xc0\xaf"), true), "\\xc0\\xaf");
	EXPECT_EQ(swba::io::mrpt_exception_summary(std::string("\xed\xa0\x80"), true), "\\xed\\xa0\\x80");
	EXPECT_EQ(swba::io::mrpt_exception_summary(std::string("a\x01z", 3), true), "a\\x01z");
}

TEST(ExceptionText, LocaleIsUtf8FromTheFirstSetVariable)
{
	{
		const Locale l(nullptr, nullptr, "en_GB.UTF-8");
		EXPECT_TRUE(swba::io::locale_is_utf8());
	}
	{
		const Locale l("C", nullptr, "en_GB.UTF-8");  // LC_ALL wins
		EXPECT_FALSE(swba::io::locale_is_utf8());
	}
	{
		const Locale l(nullptr, "C.utf8", "C");
		EXPECT_TRUE(swba::io::locale_is_utf8());
	}
	{
		const Locale l(nullptr, nullptr, nullptr);
		EXPECT_FALSE(swba::io::locale_is_utf8());
	}
}
