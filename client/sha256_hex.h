/* sha256_hex.h - the sha256 of a byte buffer as 64 lowercase hex digits: the daemon's mesh id, so the
 * client can ask whether a mesh is stored before uploading it. */
#ifndef LUCENT_SHA256_HEX_H
#define LUCENT_SHA256_HEX_H

#include <stddef.h>

#include "cli_error.h"

int sha256_hex(const void *data, size_t len, char out[65], lc_error *err);

#endif
