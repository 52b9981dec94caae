#include "suggest.h"

#include <algorithm>
#include <vector>

namespace corebox {

size_t editDistance(const std::string& a, const std::string& b) {
    std::vector<size_t> row(b.size() + 1);
    for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (size_t i = 1; i <= a.size(); ++i) {
        size_t diagonal = row[0];
        row[0] = i;
        for (size_t j = 1; j <= b.size(); ++j) {
            size_t substitute = diagonal + (a[i - 1] == b[j - 1] ? 0 : 1);
            diagonal = row[j];
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, substitute});
        }
    }
    return row[b.size()];
}

std::string didYouMean(const std::string& written, const char* const* allowed, size_t count) {
    for (size_t i = 0; i < count; ++i) {
        if (editDistance(written, allowed[i]) <= 2) return std::string(" (did you mean '") + allowed[i] + "'?)";
    }
    return "";
}

}  // namespace corebox
