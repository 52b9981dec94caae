#include "option_guards.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <thread>

namespace corebox {
namespace {

bool isIntegerLiteral(const std::string& text) {
    size_t start = (!text.empty() && (text[0] == '+' || text[0] == '-')) ? 1 : 0;
    if (start == text.size()) return false;
    for (size_t k = start; k < text.size(); ++k)
        if (text[k] < '0' || text[k] > '9') return false;
    return true;
}

// Empty when `text` is no integer literal (CLI11 judges it) or fits a signed or unsigned 64-bit
// integer; otherwise the reason.
std::string integerOverflow(const std::string& text) {
    if (!isIntegerLiteral(text)) return "";
    errno = 0;
    if (text[0] == '-') {
        (void)std::strtoll(text.c_str(), nullptr, 10);
    } else {
        (void)std::strtoull(text.c_str(), nullptr, 10);
    }
    if (errno == ERANGE) return "value " + text + " is out of the range of a 64-bit integer";
    return "";
}

bool takesIntegers(const CLI::Option& option) {
    const std::string type = option.get_type_name();
    return type.rfind("INT", 0) == 0 || type.rfind("UINT", 0) == 0;
}

}  // namespace

void addIntegerRangeChecks(CLI::App& command) {
    for (CLI::Option* option : command.get_options()) {
        if (takesIntegers(*option))
            option->check(CLI::Validator([](std::string& text) { return integerOverflow(text); }, ""));
    }
    for (CLI::App* sub : command.get_subcommands([](CLI::App*) { return true; })) addIntegerRangeChecks(*sub);
}

int capThreads(int requested, const std::string& option) {
    const int cores = int(std::max(1u, std::thread::hardware_concurrency()));
    if (requested <= cores) return requested;
    std::fprintf(stderr, "corebox: warning: %s %d is more than the %d hardware threads here; using %d\n",
                 option.c_str(), requested, cores, cores);
    return cores;
}

}  // namespace corebox
