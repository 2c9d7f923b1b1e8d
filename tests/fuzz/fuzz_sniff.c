/* fuzz_sniff.c - libFuzzer target: the upload's format from its Content-Type (the input's first line)
 * and first bytes (the rest). The answer is one of the five formats or none. */
#include "mesh_import_sandbox.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const uint8_t *nl = memchr(data, '\n', size);
    size_t type_len = nl ? (size_t)(nl - data) : 0;
    char *type = malloc(type_len + 1);
    if (!type)
        return 0;
    memcpy(type, data, type_len);
    type[type_len] = '\0';
    const uint8_t *bytes = nl ? nl + 1 : data;
    size_t len = size - (size_t)(bytes - data);
    const char *ext = mesh_format_sniff(nl ? type : NULL, bytes, len);
    static const char *const known[] = {"obj", "ply", "stl", "gltf", "glb"};
    int ok = ext == NULL;
    for (size_t i = 0; i < sizeof known / sizeof known[0]; i++)
        ok |= ext && strcmp(ext, known[i]) == 0;
    free(type);
    if (!ok)
        abort();
    return 0;
}
