/* fuzz_query.c - libFuzzer target: a GET /v1/render query string as libmicrohttpd splits it (fields on
 * '&', key and value on the first '=', '+' as a space) and lucentd decodes it (url_unescape), then the
 * query's scene (scene_query_parse). The decoded strings must hold no NUL before their end. */
#include "scene_query.h"
#include "url_unescape.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define MAX_FIELDS 64

static void decode(char *s)
{
    for (char *p = s; *p; p++)
        if (*p == '+')
            *p = ' ';
    size_t n = url_unescape(s);
    if (strlen(s) != n)
        abort();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char *text = malloc(size + 1);
    if (!text)
        return 0;
    memcpy(text, data, size);
    text[size] = '\0';   /* libmicrohttpd sees the request line as a C string */
    struct query_field fields[MAX_FIELDS];
    int count = 0;
    for (char *field = text, *next; field && count < MAX_FIELDS; field = next) {
        next = strchr(field, '&');
        if (next)
            *next++ = '\0';
        char *eq = strchr(field, '=');
        if (eq)
            *eq++ = '\0';
        decode(field);
        if (eq)
            decode(eq);
        fields[count++] = (struct query_field){field, eq};
    }
    lucent_scene scene;
    lucent_error err = {0};
    int format_given;
    scene_query_parse(fields, count, &scene, &format_given, &err);
    free(text);
    return 0;
}
