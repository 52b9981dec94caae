// The sandbox's simulated inputs (--script FILE, --scripted): a fixed sequence of the same commands the
// mouse and keyboard give, by frame number, so a session can be replayed for tests and measurements.
//
// Script file: one command a line, `FRAME COMMAND [ARGS]`, '#' starts a comment. Points on the screen
// are fractions of the window or frame (0,0 top left, 1,1 bottom right), so a script works at any size.
//   FRAME click U V          a left click at (U, V): spawns balls at the point under the cursor
//   FRAME hold U V FRAMES    the left button held at (U, V) for FRAMES frames: a spawn every 4 frames
//   FRAME remove U V         a right click at (U, V): removes the balls within 2 of the picked point
//   FRAME fire               SPACE: fires a heavy ball from the camera toward the box centre
//   FRAME orbit DYAW DPITCH  turns the camera by DYAW and DPITCH radians
//   FRAME zoom FACTOR        moves the camera: its distance times FACTOR
//   FRAME screenshot FILE    saves that frame as a PNG
//   FRAME quit               ends the session after that frame
#pragma once

#include <cstdint>
#include <istream>
#include <map>
#include <stdexcept>
#include <string>

namespace sandbox {

enum class CommandKind { Spawn, Remove, Fire, Orbit, Zoom, Screenshot, Quit };

struct Command {
    CommandKind kind = CommandKind::Spawn;
    double u = 0.5, v = 0.5;  // Spawn, Remove: window fractions; Orbit: yaw, pitch [rad]; Zoom: u the factor
    bool repeat = false;      // Spawn: a repeat of a held button (not its first press)
    std::string path;         // Screenshot
    std::string origin;       // "script.txt:3" or "built-in", for the log
};

// Commands by the frame they act in (several a frame, in script order).
using Script = std::multimap<int64_t, Command>;

// A held left button spawns once every this many frames.
constexpr int kSpawnEveryFrames = 4;

class ScriptError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// Throws ScriptError naming `name`, the line and what is wrong.
Script parseScript(std::istream& in, const std::string& name);
Script loadScript(const std::string& path);
// The built-in session of --scripted: spawn clicks and a held stream, a heavy ball fired at frame 30,
// a removal, a second shot.
Script builtInScript();

}  // namespace sandbox
