/* upload_form.c - turns a multipart/form-data mesh upload into the bytes the store takes: its one file, or
 * the canonical bundle of its files, so that the same files name the same mesh whatever the boundary. */
#include "upload_form.h"
#include "mesh_bundle.h"
#include "mesh_import_sandbox.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#define POST_BUFFER 16384 /* libmicrohttpd's buffer for part headers; the parts' bytes are copied out */

typedef struct form_part {
    char *name, *content_type;
    unsigned char *data;
    size_t len, cap;
} form_part;

typedef struct form {
    form_part parts[MESH_BUNDLE_MAX_FILES];
    size_t count;
    lucent_status status;
    lucent_error *err;
} form;

int upload_form_is_form(const char *content_type)
{
    return content_type && strncasecmp(content_type, "multipart/form-data", 19) == 0;
}

static enum MHD_Result refuse(form *f, lucent_status status, const char *field, const char *message)
{
    f->status = lucent_fail(f->err, status, field, "%s", message);
    return MHD_NO;
}

static int begin_part(form *f, const char *filename, const char *content_type)
{
    form_part *p = &f->parts[f->count];
    p->name = strdup(filename);
    p->content_type = strdup(content_type ? content_type : "");
    f->count++;
    return p->name && p->content_type;
}

static int append(form_part *p, const char *data, size_t size)
{
    if (size > p->cap - p->len) {
        size_t cap = p->cap ? p->cap : 4096;
        while (cap - p->len < size)
            cap *= 2;
        unsigned char *bigger = realloc(p->data, cap);
        if (!bigger)
            return 0;
        p->data = bigger;
        p->cap = cap;
    }
    memcpy(p->data + p->len, data, size);
    p->len += size;
    return 1;
}

/* libmicrohttpd calls this with each part's bytes in order, offset 0 starting a part (an empty part may
 * be announced with no bytes before its first chunk, also at offset 0). */
static enum MHD_Result take_chunk(void *cls, enum MHD_ValueKind kind, const char *key, const char *filename,
                                  const char *content_type, const char *transfer_encoding, const char *data,
                                  uint64_t off, size_t size)
{
    form *f = cls;
    (void)kind, (void)key;
    if (!filename)
        return refuse(f, LUCENT_E_INVALID, "body", "every part of the form must be a file (with a filename)");
    if (transfer_encoding && strcasecmp(transfer_encoding, "binary") != 0 &&
        strcasecmp(transfer_encoding, "8bit") != 0 && strcasecmp(transfer_encoding, "7bit") != 0)
        return refuse(f, LUCENT_E_INVALID, "body", "send the form's files as they are, without a transfer encoding");
    form_part *last = f->count ? &f->parts[f->count - 1] : NULL;
    int announced = last && off == 0 && last->len == 0 && strcmp(last->name, filename) == 0;
    if (off == 0 && !announced) {
        if (f->count == MESH_BUNDLE_MAX_FILES)
            return refuse(f, LUCENT_E_INVALID, "body", "the form holds more than 64 files");
        if (!begin_part(f, filename, content_type))
            return refuse(f, LUCENT_E_NOMEM, "body", "out of memory reading the form");
        last = &f->parts[f->count - 1];
    }
    if (size && !append(last, data, size))
        return refuse(f, LUCENT_E_NOMEM, "body", "out of memory reading the form");
    return MHD_YES;
}

static void free_form(form *f)
{
    for (size_t i = 0; i < f->count; i++) {
        free(f->parts[i].name);
        free(f->parts[i].content_type);
        free(f->parts[i].data);
    }
}

static lucent_status parse(struct MHD_Connection *connection, const unsigned char *body, size_t len, form *f)
{
    struct MHD_PostProcessor *pp = MHD_create_post_processor(connection, POST_BUFFER, take_chunk, f);
    if (!pp)
        return lucent_fail(f->err, LUCENT_E_INVALID, "Content-Type",
                           "multipart/form-data needs a boundary parameter");
    enum MHD_Result parsed = MHD_post_process(pp, (const char *)body, len);
    enum MHD_Result complete = MHD_destroy_post_processor(pp);
    if (f->status != LUCENT_OK)
        return f->status;
    if (parsed != MHD_YES || complete != MHD_YES)
        return lucent_fail(f->err, LUCENT_E_INVALID, "body", "the body is not well-formed multipart/form-data");
    if (f->count == 0)
        return lucent_fail(f->err, LUCENT_E_INVALID, "body", "the form holds no file");
    return LUCENT_OK;
}

static lucent_status bundle(form *f, unsigned char **bytes, size_t *bytes_len, lucent_error *err)
{
    lucent_mesh_file files[MESH_BUNDLE_MAX_FILES];
    for (size_t i = 0; i < f->count; i++)
        files[i] = (lucent_mesh_file){f->parts[i].name, f->parts[i].data, f->parts[i].len};
    size_t main;
    const char *ext;
    lucent_status st = mesh_bundle_check(files, f->count, &main, &ext, err);
    return st == LUCENT_OK ? mesh_bundle_encode(files, f->count, bytes, bytes_len, err) : st;
}

lucent_status upload_form_read(struct MHD_Connection *connection, const unsigned char *body, size_t len,
                               unsigned char **bytes, size_t *bytes_len, const char **format, lucent_error *err)
{
    form f = {.status = LUCENT_OK, .err = err};
    lucent_status st = parse(connection, body, len, &f);
    if (st == LUCENT_OK && f.count == 1) {
        form_part *p = &f.parts[0];
        *format = mesh_upload_format(p->content_type, p->data, p->len, err);
        st = *format ? LUCENT_OK : LUCENT_E_INVALID;
        if (st == LUCENT_OK) {
            *bytes = p->data ? p->data : malloc(1);
            *bytes_len = p->len;
            p->data = NULL;
            st = *bytes ? LUCENT_OK : lucent_fail(err, LUCENT_E_NOMEM, "body", "out of memory reading the form");
        }
    } else if (st == LUCENT_OK) {
        *format = "bundle";
        st = bundle(&f, bytes, bytes_len, err);
    }
    free_form(&f);
    return st;
}
