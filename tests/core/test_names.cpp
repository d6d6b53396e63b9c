// The enum <-> string mechanism (swba/core/names.h).
#include <gtest/gtest.h>
#include <swba/core/loss.h>
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

enum class Gauge
{
	Fixed,
	Free
};
constexpr std::array<swba::EnumName<Gauge>, 3> enum_names(Gauge)
{
	return {{{Gauge::Fixed, "fixed"}, {Gauge::Free, "free"}, {Gauge::Fixed, "fix", true}}};
}
}  // namespace names_test

using names_test::Color;
using names_test::Gauge;

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
		EXPECT_STREQ(e.what(), "unknown color 'Red' (expected red, green or blue)");
	}
	EXPECT_EQ(swba::enum_choices<Color>(" | "), "red | green | blue");
	EXPECT_EQ(swba::enum_choices_sentence<Color>(), "red, green or blue");
}

TEST(Names, ValueOutsideTheTableIsALogicError)
{
	EXPECT_THROW((void)swba::enum_name(static_cast<Color>(7)), std::logic_error);
}

TEST(Names, AnAliasIsAcceptedButNeverPrintedOrListed)
{
	EXPECT_EQ(swba::parse_enum<Gauge>("fix", "gauge"), Gauge::Fixed);
	EXPECT_EQ(swba::enum_name(Gauge::Fixed), "fixed");
	EXPECT_EQ(swba::enum_choices<Gauge>(), "fixed, free");
	EXPECT_EQ(swba::enum_choices_sentence<Gauge>(), "fixed or free");
}

TEST(Names, RobustLossNamesAreTheOnesMakeLossTakes)
{
	for (const auto& row : swba::enum_table<swba::RobustLoss>())
		EXPECT_EQ(swba::make_loss(row.name, 1.0) == nullptr, row.value == swba::RobustLoss::None) << row.name;
	EXPECT_EQ(swba::parse_enum<swba::RobustLoss>("", "loss"), swba::RobustLoss::None);
	EXPECT_EQ(swba::enum_choices_sentence<swba::RobustLoss>(), "none, huber or cauchy");
}
