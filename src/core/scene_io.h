// Scene files: TOML text <-> Scene (DESIGN.md sec. 3).
//
// Design note. Reading is two steps with one purpose each: scene_parse.cpp reads the TOML tree
// (syntax, allowed tables and keys, types, names of choices) and notes the line of every key;
// scene_validation.h checks the values against the rules, naming "file:line: key" through those
// notes ("scene.toml:12: species[1].mass: must be > 0"). Unknown tables and keys are errors (a typo
// must never silently fall back to a default), and the message lists the allowed keys with a "did
// you mean" (suggest.h). Missing keys take the struct defaults of scene.h, except that each
// [[species]] must give `count`, and species without a name or colour are named "A", "B", ... and
// coloured from a palette by position, so that two unnamed species do not collide.
//
// Writing (scene_serialise.cpp) is hand-written rather than via toml++'s formatter: it keeps the
// sections in the documented order and writes doubles in their shortest round-trip form, so
// parseScene(sceneToToml(s)) reproduces every field of s exactly.
#pragma once

#include <string>

#include "scene.h"

namespace corebox {

// Parses and validates scene text; `sourceName` names the text in error messages. Throws
// InputError with locatedMessage(sourceName, line, key, message). init.particles is kept as written.
Scene parseScene(const std::string& text, const std::string& sourceName);

// Reads and parses the file at `path`; sets sourcePath = path and resolves a relative
// init.particles against the scene file's directory. Throws InputError when the file cannot be read.
Scene loadScene(const std::string& path);

// TOML text that parseScene reads back to the same Scene (colours as "#rrggbb", so a colour
// survives the round trip when it is a multiple of 1/255, which parsed colours always are).
std::string sceneToToml(const Scene& scene);

// Writes sceneToToml(scene) atomically. A relative init.particles (relative to the working
// directory, as loadScene leaves it) is rewritten relative to the new file's directory, so
// loadScene(path) finds the same particle file.
void saveScene(const Scene& scene, const std::string& path);

}  // namespace corebox
