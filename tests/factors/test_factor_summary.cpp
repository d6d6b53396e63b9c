// Prints the worst Jacobian error seen per factor when the factor test binary ends (run it directly).
#include "factor_test_fixtures.h"

#include <cstdio>

namespace
{
class PrintWorstJacobianErrors : public ::testing::Environment
{
   public:
	void TearDown() override
	{
		for (const auto& [name, err] : swba::factor_test::WorstErrors::table())
			std::printf("[jacobians] %-40s worst relative error %.3e\n", name.c_str(), err);
	}
};
const auto* const kRegistered = ::testing::AddGlobalTestEnvironment(new PrintWorstJacobianErrors);
}  // namespace
