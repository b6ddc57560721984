// Private helpers of the mesh file writers: number formatting and all-or-nothing file output.
#pragma once

#include "polycut/common/types.hpp"

#include <string>

namespace polycut::mesh::io {

/// Appends the shortest text that reads back as exactly v ("nan", "inf" for non-finite values).
void append_number(std::string& out, double v);
/// Appends an integer.
void append_number(std::string& out, long v);

/// Writes `content` to path + ".part", then renames it to `path`, so a reader sees the old file
/// or the whole new one. Throws FileError(path, 0, ...) on failure (the part file is removed).
void write_file(const std::string& path, const std::string& content);

} // namespace polycut::mesh::io
