/* upload_form.h - a mesh upload sent as multipart/form-data (curl -F, a browser's FormData): the files are
 * read with libmicrohttpd's post processor and become one upload, one file as itself, several as a bundle. */
#ifndef LUCENTD_UPLOAD_FORM_H
#define LUCENTD_UPLOAD_FORM_H

#include "lucent.h"

#include <microhttpd.h>
#include <stddef.h>

/* 1 if the Content-Type is multipart/form-data. */
int upload_form_is_form(const char *content_type);

/* Reads the form body of `connection`'s request (its Content-Type gives the boundary). Every part must
 * be a file (a filename); a form with one file gives that file's bytes and the format its part's type
 * and bytes name (mesh_upload_format); with more, their mesh_bundle encoding and the format "bundle".
 * *bytes is malloc'd, the caller's. Errors are LUCENT_E_INVALID naming the field "body" (or
 * "Content-Type"), or LUCENT_E_NOMEM. */
lucent_status upload_form_read(struct MHD_Connection *connection, const unsigned char *body, size_t len,
                               unsigned char **bytes, size_t *bytes_len, const char **format, lucent_error *err);

#endif
