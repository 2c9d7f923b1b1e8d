/* scene_query.h - GET /v1/render's flat query fields, turned into the scene document POST takes and
 * parsed by the same lucent_scene_parse, so both requests give the same scene and the same bytes. */
#ifndef LUCENTD_SCENE_QUERY_H
#define LUCENTD_SCENE_QUERY_H

#include "lucent.h"

struct query_field {
    const char *key, *value;  /* value NULL for a bare "?key" */
};

/* Builds the scene document from the fields and parses it (files never allowed). Errors name the
 * query field (e.g. "sigma_a[1]"). *format_given says whether "format" was among the fields. */
lucent_status scene_query_parse(const struct query_field *fields, int count, lucent_scene *out, int *format_given,
                                lucent_error *err);
/* The field a problem about an unknown query key names: the key when it is spelt like a field name, else
 * "query" (the field picks the status, problem.c, so "?Content-Type=1" would make a 415). */
const char *query_key_field(const char *key);
/* The scene document (malloc'd JSON text) the fields map to; NULL on error (err filled). */
char *scene_query_document(const struct query_field *fields, int count, lucent_error *err);

#endif
