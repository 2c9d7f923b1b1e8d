/* json_text.c - compact JSON with short numbers (contract in json_text.h). jansson prints every real
 * with one precision per document (17 digits by default), so the document gets the fewest digits that
 * give each of its numbers back exactly: up to 15 digits a double prints as its shortest form padded
 * with zeros, which %g drops. */
#include "json_text.h"

#include <stdio.h>
#include <stdlib.h>

/* Fewest significant digits (1-17) whose %g text reads back as v. */
static int shortest_digits(double v)
{
    char buf[40];
    for (int p = 1; p < 17; p++) {
        snprintf(buf, sizeof buf, "%.*g", p, v);
        if (strtod(buf, NULL) == v)
            return p;
    }
    return 17;
}

static int digits_needed(const json_t *v)
{
    int most = 1;
    if (json_is_real(v))
        return shortest_digits(json_real_value(v));
    if (json_is_array(v)) {
        size_t i;
        const json_t *item;
        json_array_foreach(v, i, item) {
            int d = digits_needed(item);
            most = d > most ? d : most;
        }
    } else if (json_is_object(v)) {
        const char *key;
        const json_t *item;
        json_object_foreach((json_t *)v, key, item) {
            int d = digits_needed(item);
            most = d > most ? d : most;
        }
    }
    return most;
}

char *json_text(const json_t *doc)
{
    return json_dumps(doc, JSON_COMPACT | JSON_REAL_PRECISION(digits_needed(doc)));
}
