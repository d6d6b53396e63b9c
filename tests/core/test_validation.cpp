// The options structs' validation convention (swba/core/validation.h) and the steady-clock helper
// (swba/core/timing.h).
#include <swba/core/timing.h>
#include <swba/core/validation.h>

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace
{
struct PositiveOption
{
	double value = 1;
	void validate() const
	{
		if (!(value > 0)) throw std::invalid_argument("value must be > 0");
	}
};
}  // namespace

TEST(Validation, PrefixIsPutBeforeTheOptionsOwnMessage)
{
	PositiveOption o;
	EXPECT_NO_THROW(swba::validate_with_prefix(o, "[section]: "));
	o.value = -1;
	try
	{
		swba::validate_with_prefix(o, "[section]: ");
		FAIL() << "no error";
	}
	catch (const std::invalid_argument& e)
	{
		EXPECT_EQ(std::string(e.what()), "[section]: value must be > 0");
	}
}

TEST(Timing, SecondsSinceIsNonNegativeAndGrows)
{
	const auto t0 = swba::SteadyClock::now();
	const double a = swba::seconds_since(t0);
	const double b = swba::seconds_since(t0);
	EXPECT_GE(a, 0.0);
	EXPECT_GE(b, a);
}
