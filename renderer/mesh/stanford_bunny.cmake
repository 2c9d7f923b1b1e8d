# stanford_bunny.cmake - converts the Stanford bunny of the npm package "bunny" (renderer/mesh/data/stanford_bunny.js:
# exports.positions, exports.cells) into C arrays at build time (cmake -P). Inputs: IN, OUT.
file(READ ${IN} js)
string(REGEX MATCH "exports\\.positions=(\\[[][0-9.e,-]*\\])" found "${js}")
set(positions "${CMAKE_MATCH_1}")
string(REGEX MATCH "exports\\.cells=(\\[[][0-9,]*\\])" found "${js}")
set(cells "${CMAKE_MATCH_1}")
if(NOT positions OR NOT cells)
  message(FATAL_ERROR "${IN}: exports.positions or exports.cells not found")
endif()
foreach(list positions cells)
  string(REPLACE "[" "{" ${list} "${${list}}")
  string(REPLACE "]" "}" ${list} "${${list}}")
  string(REPLACE "},{" "},\n{" ${list} "${${list}}")
endforeach()
file(WRITE ${OUT} "/* Generated from ${IN} by stanford_bunny.cmake; do not edit. */\n"
  "#include \"stanford_bunny.h\"\n\n"
  "const float stanford_bunny_positions[][3] = ${positions};\n"
  "const uint32_t stanford_bunny_vertex_count = sizeof stanford_bunny_positions / sizeof stanford_bunny_positions[0];\n\n"
  "const uint32_t stanford_bunny_triangles[][3] = ${cells};\n"
  "const uint32_t stanford_bunny_triangle_count = sizeof stanford_bunny_triangles / sizeof stanford_bunny_triangles[0];\n")
