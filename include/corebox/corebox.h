// corebox: hard-core particles in a rigid box, as a library. Include this one header.
//
//   corebox::World world(corebox::WorldDef{});            // a 30 x 60 x 30 box under gravity
//   world.addParticle({0, {15, 30, 15}, {0, 0, 0}});        // species 0 at the centre
//   for (int frame = 0; frame < 60; ++frame) world.advance(1.0 / 60.0);
//
// world.h has the API and its design note; errors.h the exceptions; corebox_c.h the C interface
// (include it on its own).
#pragma once

#include "corebox/errors.h"
#include "corebox/export.h"
#include "corebox/types.h"
#include "corebox/world.h"

namespace corebox {

// The library's version, "major.minor.patch" (also COREBOX_VERSION in coreboxConfigVersion.cmake).
COREBOX_API const char* version();

}  // namespace corebox
