#include "sandbox_script.h"

#include <cmath>
#include <fstream>
#include <sstream>

namespace sandbox {
namespace {

bool fraction(double x) { return std::isfinite(x) && x >= 0.0 && x <= 1.0; }

}  // namespace

Script parseScript(std::istream& in, const std::string& name) {
    Script script;
    std::string line;
    int lineNo = 0;
    while (std::getline(in, line)) {
        ++lineNo;
        const size_t hash = line.find('#');
        if (hash != std::string::npos) line.resize(hash);
        std::istringstream words(line);
        std::string frameText, verb;
        if (!(words >> frameText)) continue;  // blank or comment
        const std::string where = name + ":" + std::to_string(lineNo);
        auto fail = [&](const std::string& what) -> ScriptError { return ScriptError(where + ": " + what); };
        size_t used = 0;
        long long frame = -1;
        try {
            frame = std::stoll(frameText, &used);
        } catch (const std::exception&) {
            used = 0;
        }
        if (used != frameText.size() || frame < 0) throw fail("'" + frameText + "' is not a frame number (0, 1, ...)");
        if (!(words >> verb)) throw fail("a command must follow the frame number");
        Command c;
        c.origin = where;
        auto point = [&]() {
            if (!(words >> c.u >> c.v) || !fraction(c.u) || !fraction(c.v))
                throw fail(verb + " needs U V, fractions of the window in [0, 1]");
        };
        int64_t heldFrames = 1;
        if (verb == "click") {
            c.kind = CommandKind::Spawn;
            point();
        } else if (verb == "hold") {
            c.kind = CommandKind::Spawn;
            point();
            if (!(words >> heldFrames) || heldFrames < 1) throw fail("hold needs U V FRAMES, FRAMES >= 1");
        } else if (verb == "remove") {
            c.kind = CommandKind::Remove;
            point();
        } else if (verb == "fire") {
            c.kind = CommandKind::Fire;
        } else if (verb == "orbit") {
            c.kind = CommandKind::Orbit;
            if (!(words >> c.u >> c.v) || !std::isfinite(c.u) || !std::isfinite(c.v))
                throw fail("orbit needs DYAW DPITCH in radians");
        } else if (verb == "zoom") {
            c.kind = CommandKind::Zoom;
            if (!(words >> c.u) || !std::isfinite(c.u) || c.u <= 0) throw fail("zoom needs FACTOR > 0");
        } else if (verb == "screenshot") {
            c.kind = CommandKind::Screenshot;
            if (!(words >> c.path)) throw fail("screenshot needs a file name");
        } else if (verb == "quit") {
            c.kind = CommandKind::Quit;
        } else {
            throw fail("unknown command '" + verb + "' (click, hold, remove, fire, orbit, zoom, screenshot, quit)");
        }
        std::string extra;
        if (words >> extra) throw fail("unexpected '" + extra + "' after " + verb);
        for (int64_t k = 0; k < heldFrames; k += kSpawnEveryFrames) {
            c.repeat = k > 0;
            script.emplace(frame + k, c);
        }
    }
    return script;
}

Script loadScript(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw ScriptError("--script: cannot open '" + path + "'");
    return parseScript(in, path);
}

Script builtInScript() {
    // Window fractions under the default camera (above and to the side of the box's centre): v = 0.3
    // is high in the box; the removals aim at the falling start lattice (its top layer near y = 54 at
    // frame 60, y = 44 at frame 105) and hit it from 500 to 2000 balls.
    static const char* const text =
        "10 click 0.50 0.30\n"
        "16 click 0.42 0.32\n"
        "22 hold 0.58 0.28 24\n"  // a stream: a spawn every 4 frames for 24 frames
        "30 fire\n"
        "60 remove 0.50 0.22\n"
        "75 click 0.50 0.30\n"
        "90 fire\n"
        "105 remove 0.50 0.34\n";
    std::istringstream in(text);
    Script script = parseScript(in, "built-in");
    for (auto& entry : script) entry.second.origin = "built-in";
    return script;
}

}  // namespace sandbox
