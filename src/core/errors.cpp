#include "errors.h"

namespace corebox {

std::string locatedMessage(const std::string& file, long line, const std::string& key, const std::string& message) {
    std::string out = file.empty() ? std::string("<scene>") : file;
    if (line > 0) out += ":" + std::to_string(line);
    out += ": ";
    if (!key.empty()) out += key + ": ";
    return out + message;
}

}  // namespace corebox
