/* json_text.h - the JSON text lucentd answers with: compact, and every number the shortest decimal that
 * reads back to the same double (0.003, not jansson's 0.0030000000000000001). */
#ifndef LUCENTD_JSON_TEXT_H
#define LUCENTD_JSON_TEXT_H

#include <jansson.h>

/* The document as compact text (free() it), or NULL when out of memory. */
char *json_text(const json_t *doc);

#endif
