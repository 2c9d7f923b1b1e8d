/* file_io.h - local files: whole-file reads (meshes, scenes, the token) and image output that never
 * leaves a partial file behind (written to a temp file beside the target, renamed on success). */
#ifndef LUCENT_FILE_IO_H
#define LUCENT_FILE_IO_H

#include <stddef.h>
#include <stdio.h>

#include "cli_error.h"

/* The whole file in *data (NUL-terminated, owned by the caller); LC_E_FILE naming the path on failure. */
int file_read_all(const char *path, char **data, size_t *len, lc_error *err);

struct output_file {
    const char *path; /* the target; "-" is standard output */
    char *tmp_path;   /* NULL for standard output, whose bytes wait in an anonymous temp file */
    FILE *fp;
};

int output_open(struct output_file *out, const char *path, lc_error *err);
/* Flushes and renames (or copies to standard output); the output is closed either way. */
int output_commit(struct output_file *out, lc_error *err);
/* Removes the temp file; safe on an output that was never opened or already committed. */
void output_abort(struct output_file *out);

#endif
