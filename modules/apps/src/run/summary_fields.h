// The association counts of summary.json and ape.csv, named once for the writer (run/report.cpp) and
// the reader (sweep/summary_json.cpp). Internal to the applications.
#pragma once

#include <swba/estimators/association_quality.h>

#include <cstddef>
#include <utility>
#include <vector>

namespace swba::apps
{
/** (name, member) of every count of estimators::AssociationQuality, in the files' order. */
inline const std::vector<std::pair<const char*, std::size_t estimators::AssociationQuality::*>>& association_fields()
{
	using Q = estimators::AssociationQuality;
	static const std::vector<std::pair<const char*, std::size_t Q::*>> f = {
		{"readings", &Q::readings},	  {"associated", &Q::associated}, {"correct", &Q::correct},
		{"landmarks", &Q::landmarks}, {"true_landmarks", &Q::true_landmarks}, {"duplicates", &Q::duplicates},
		{"spurious", &Q::spurious}};
	return f;
}
}  // namespace swba::apps
