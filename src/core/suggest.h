// "Did you mean ...?" for a misspelt name: the first allowed name within two edits (insert, delete,
// substitute) of what was written. Scene files use it for unknown tables and keys.
#pragma once

#include <cstddef>
#include <string>

namespace corebox {

// Levenshtein distance.
size_t editDistance(const std::string& a, const std::string& b);

// " (did you mean 'size'?)" when one of the `count` names in `allowed` is within two edits of
// `written`, else "".
std::string didYouMean(const std::string& written, const char* const* allowed, size_t count);

}  // namespace corebox
