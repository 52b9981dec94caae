#include "script.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <set>
#include <sstream>

#include "errors.h"

namespace corebox {
namespace {

// Expected argument counts; -1: at least one.
int argumentCount(const std::vector<std::string>& w) {
    if (w[0] == "set") {
        if (w.size() < 2) return -2;
        static const std::set<std::string> one{"temperature", "thermostat", "tau", "method", "dt", "precision",
                                               "restitution", "wall-restitution", "color", "steps-per-frame"};
        if (one.count(w[1])) return 2;
        if (w[1] == "gravity" || w[1] == "mixing") return 4;
        return -3;
    }
    if (w[0] == "pause" || w[0] == "resume" || w[0] == "reset" || w[0] == "quit") return 0;
    if (w[0] == "screenshot") return 1;
    return -4;
}

}  // namespace

Script Script::load(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw InputError("--script: cannot read '" + path + "': " + std::strerror(errno));
    Script script;
    script.m_path = path;
    std::string text;
    long lineNo = 0;
    while (std::getline(in, text)) {
        ++lineNo;
        const size_t hash = text.find('#');
        if (hash != std::string::npos) text.resize(hash);
        std::istringstream words(text);
        std::string stepText;
        if (!(words >> stepText)) continue;
        ScriptCommand c;
        c.line = lineNo;
        char* end = nullptr;
        c.step = std::strtoll(stepText.c_str(), &end, 10);
        if (*end != '\0' || c.step < 0) throw InputError(locatedMessage(path, lineNo, "", "expected a step number, got '" + stepText + "'"));
        for (std::string w; words >> w;) c.words.push_back(w);
        if (c.words.empty()) throw InputError(locatedMessage(path, lineNo, "", "missing command after the step"));
        const int expected = argumentCount(c.words);
        if (expected == -4) throw InputError(locatedMessage(path, lineNo, c.words[0], "unknown command (set, pause, resume, reset, screenshot, quit)"));
        if (expected == -3 || expected == -2) {
            throw InputError(locatedMessage(path, lineNo, "set", "unknown setting '" + (c.words.size() > 1 ? c.words[1] : "") + "'"));
        }
        if (int(c.words.size()) - 1 != expected) {
            throw InputError(locatedMessage(path, lineNo, c.words[0], "expected " + std::to_string(expected) + " argument(s)"));
        }
        script.m_commands.push_back(c);
    }
    std::stable_sort(script.m_commands.begin(), script.m_commands.end(),
                     [](const ScriptCommand& a, const ScriptCommand& b) { return a.step < b.step; });
    return script;
}

std::vector<ScriptCommand> Script::due(int64_t step) {
    std::vector<ScriptCommand> out;
    while (m_next < m_commands.size() && m_commands[m_next].step <= step) out.push_back(m_commands[m_next++]);
    return out;
}

}  // namespace corebox
