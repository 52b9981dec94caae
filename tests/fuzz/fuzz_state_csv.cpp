// libFuzzer target: particle state CSV through its reader. Any input must end in a ParticleState or
// an InputError; anything else (a crash, a sanitizer report, another exception) is a bug.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "errors.h"
#include "state_csv.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
    try {
        (void)corebox::parseStateCsv(in, "fuzz.csv");
    } catch (const corebox::InputError&) {
    }
    return 0;
}
