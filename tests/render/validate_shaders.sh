#!/usr/bin/env bash
# Every shader in shaders/ must compile and link with glslangValidator, as the programs the renderer
# builds (src/render/particle_renderer.cpp). A shader file that belongs to no program fails too, so
# a new shader cannot slip past validation.
set -u
dir=${1:?shader directory}
# viridis.frag before sphere.frag: glslang's linker takes a redeclared gl_FragDepth layout
# (sphere.frag's depth_greater) only from a unit after those without one, and otherwise reports
# "Contradictory depth layouts" for a unit that, as viridis.frag, never writes the depth (which GLSL
# allows: only shaders that assign gl_FragDepth must redeclare it).
programs=("sphere.vert viridis.frag sphere.frag" "lines.vert flat.frag" "overlay.vert overlay.frag viridis.frag")
failed=0
covered=" "
for program in "${programs[@]}"; do
    (cd "$dir" && glslangValidator -l $program >/dev/null) || { echo "FAIL: $program"; (cd "$dir" && glslangValidator -l $program); failed=1; }
    covered+="$program "
done
# The sphere program's flat-depth variant (RenderStyle::exactDepth false), as the renderer builds it.
(cd "$dir" && glslangValidator -DCOREBOX_FLAT_DEPTH -l sphere.vert viridis.frag sphere.frag >/dev/null) ||
    { echo "FAIL: sphere program with COREBOX_FLAT_DEPTH"; (cd "$dir" && glslangValidator -DCOREBOX_FLAT_DEPTH -l sphere.vert viridis.frag sphere.frag); failed=1; }
for f in "$dir"/*.vert "$dir"/*.frag; do
    name=$(basename "$f")
    [[ "$covered" == *" $name "* ]] || { echo "FAIL: $name is in no validated program"; failed=1; }
done
[ "$failed" -eq 0 ] && echo "all shaders validated"
exit "$failed"
