// Shipped BAL problems used by the tests of tests/bal.
#pragma once

#include <string>

inline const std::string kShrink = std::string(SWBA_DATA_DIR) + "/bal/bal-ladybug-problem-49-7776-pre-shrink-1800.txt";
