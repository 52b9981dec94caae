// Scripted runs (`--script FILE`) for tests and demos, the same in the window and headless. Each
// line is "STEP COMMAND [ARGS]": the command runs once the simulation has reached STEP.
//
//   set temperature KT | set thermostat bussi|rescale|none | set tau T | set method NAME
//   set dt DT | set precision fp32|fp64 | set restitution E | set wall-restitution E
//   set gravity GX GY GZ | set mixing I J X | set color species|speed | set steps-per-frame K
//   pause | resume | reset | screenshot FILE.png | quit
//
// Blank lines and '#' comments are ignored; errors name the file and line.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace corebox {

struct ScriptCommand {
    int64_t step = 0;
    std::vector<std::string> words;  // command and arguments
    long line = 0;
};

class Script {
public:
    Script() = default;
    // Throws InputError naming FILE:LINE for unknown commands or bad arguments.
    static Script load(const std::string& path);

    // Commands due at `step` (in file order), each returned once.
    std::vector<ScriptCommand> due(int64_t step);
    bool empty() const { return m_commands.empty(); }
    const std::string& path() const { return m_path; }

private:
    std::string m_path;
    std::vector<ScriptCommand> m_commands;
    size_t m_next = 0;
};

}  // namespace corebox
