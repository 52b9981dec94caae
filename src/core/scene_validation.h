// Scene validation: every rule on the values of a Scene once it has been read, apart from the
// file's syntax and types (scene_parse.cpp). Ranges (mass > 0, restitution in [0, 1], ...), unique
// species names, a symmetric mixing matrix, `adaptive` only with dp5, and hard cores that fit the
// box (packing.h, the rule the initial placement applies too).
//
// Design note. Validation is separate from parsing so that each has one purpose, yet its errors
// still name "file:line: key": the parser records in SceneLocations the line of every key it read
// (the line of the enclosing table for a key left out, so that a default failing a cross-check
// still points somewhere useful), and the validator looks the line up by the dotted key.
#pragma once

#include <string>
#include <unordered_map>

#include "scene.h"

namespace corebox {

class SceneLocations {
public:
    explicit SceneLocations(std::string file = "") : m_file(std::move(file)) {}

    void set(const std::string& key, long line) { m_lines[key] = line; }
    long line(const std::string& key) const;  // 0 when not recorded (a scene built in code)
    const std::string& file() const { return m_file; }

    // Throws InputError(locatedMessage(file, line(key), key, message)).
    [[noreturn]] void fail(const std::string& key, const std::string& message) const;

private:
    std::string m_file;
    std::unordered_map<std::string, long> m_lines;
};

// Throws InputError for the first rule the scene breaks, located through `where`.
void validateScene(const Scene& scene, const SceneLocations& where);

}  // namespace corebox
