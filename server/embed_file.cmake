# embed_file.cmake - writes a file's bytes as a C array (cmake -P), so lucentd serves its OpenAPI
# document with no file lookup at run time. Inputs: IN, OUT, NAME.
file(READ ${IN} hex HEX)
string(LENGTH "${hex}" hex_len)
math(EXPR size "${hex_len} / 2")
string(REGEX REPLACE "([0-9a-f][0-9a-f])" "0x\\1," bytes "${hex}")
file(WRITE ${OUT} "/* Generated from ${IN} by embed_file.cmake; do not edit. */\n#include <stddef.h>\n"
  "const unsigned char ${NAME}[] = {${bytes}0x00};\nconst size_t ${NAME}_len = ${size};\n")
