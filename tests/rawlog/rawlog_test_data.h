// Where the tests of tests/rawlog find mrpt-common's rawlogs.
#pragma once

#include <string>

inline const std::string kDatasets = SWBA_MRPT_DATASETS;
