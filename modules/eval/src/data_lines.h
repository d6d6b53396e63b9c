/** \file data_lines.h
 * The line loop of the eval text readers (TUM, MRPT ground truth, covariance files): which lines
 * hold data, how they are numbered, and the read error at the end. Private to eval. */
#pragma once

#include <swba/eval/trajectory.h>

#include <istream>
#include <string>

namespace swba::eval::detail
{
/** True if the line holds no data: blank, or its first non-blank character is `comment`. */
inline bool is_comment_or_blank(const std::string& line, char comment)
{
	for (char c : line)
	{
		if (c == ' ' || c == '\t' || c == '\r' || c == '\n') continue;
		return c == comment;
	}
	return true;
}

/** Calls row(line, line_no) for each data line of `in` (line_no counts every line from 1); throws
 * TrajectoryFileError naming `source` on a read error. */
template <class Row>
void for_each_data_line(std::istream& in, const std::string& source, char comment, Row row)
{
	std::string line;
	std::size_t line_no = 0;
	while (std::getline(in, line))
	{
		line_no++;
		if (!is_comment_or_blank(line, comment)) row(line, line_no);
	}
	if (in.bad()) throw TrajectoryFileError(source, 0, "read error");
}
}  // namespace swba::eval::detail
