// libFuzzer target: scene text (TOML) through the parser and the validator. Any input must end in a
// Scene or an InputError; anything else (a crash, a sanitizer report, another exception) is a bug.
#include <cstddef>
#include <cstdint>
#include <string>

#include "errors.h"
#include "scene_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    try {
        (void)corebox::parseScene(text, "fuzz.toml");
    } catch (const corebox::InputError&) {
    }
    return 0;
}
