/** \file validation.h
 * The options structs' one validation convention: `void validate() const`, which throws
 * std::invalid_argument whose message names the offending option and says what it must be. Every
 * caller of an is-it-valid check threw on failure anyway; a throwing validate() says so once, nests
 * (an options struct validates the options it holds), and lets the command line turn the exception
 * into a usage error (exit 2) in one place. */
#pragma once

#include <stdexcept>
#include <string>

namespace swba
{
/** options.validate(), the message of its std::invalid_argument prefixed by `prefix` (the caller's
 * context, e.g. "[imu]: " or "SolverOptions: "). */
template <class Options>
void validate_with_prefix(const Options& options, const std::string& prefix)
{
	try
	{
		options.validate();
	}
	catch (const std::invalid_argument& e)
	{
		throw std::invalid_argument(prefix + e.what());
	}
}
}  // namespace swba
