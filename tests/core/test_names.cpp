// The enum <-> string mechanism (swba/core/names.h).
#include <gtest/gtest.h>
#include <swba/core/names.h>

namespace names_test
{
enum class Color
{
	Red,
	Green,
	Blue
};
constexpr std::array<swba::EnumName<Color>, 3> enum_names(Color)
{
	return {{{Color::Red, "red"}, {Color::Green, "green"}, {Color::Blue, "blue"}}};
}
}  // namespace names_test

using names_test::Color;

TEST(Names, EveryValueRoundTrips)
{
	for (const auto& row : swba::enum_table<Color>())
	{
		EXPECT_EQ(swba::enum_name(row.value), row.name);
		EXPECT_EQ(swba::parse_enum<Color>(row.name, "color"), row.value);
	}
	EXPECT_EQ(swba::enum_name(Color::Green), "green");
	EXPECT_EQ(swba::parse_enum<Color>("blue", "color"), Color::Blue);
}

TEST(Names, UnknownNameListsTheValidOnes)
{
	try
	{
		(void)swba::parse_enum<Color>("Red", "color");  // exact match only
		FAIL() << "no exception";
	}
	catch (const std::invalid_argument& e)
	{
		EXPECT_STREQ(e.what(), "unknown color 'Red' (valid: red, green, blue)");
	}
	EXPECT_EQ(swba::enum_choices<Color>(" | "), "red | green | blue");
}

TEST(Names, ValueOutsideTheTableIsALogicError)
{
	EXPECT_THROW((void)swba::enum_name(static_cast<Color>(7)), std::logic_error);
}
