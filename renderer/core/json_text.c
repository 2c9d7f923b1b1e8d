/* json_text.c - numbers and strings for the JSON the renderer prints: an unescaped device name or a
 * NaN measure ("nan") made --stats and --compare output that JSON parsers refuse. */
#include "json_text.h"

#include <math.h>
#include <stdio.h>

void json_number(double v, char *out, size_t cap)
{
    snprintf(out, cap, isfinite(v) ? "%.6g" : "null", v);
}

void json_escape(const char *s, char *out, size_t cap)
{
    size_t n = 0;
    for (; *s && cap > 0; s++) {
        unsigned char c = (unsigned char)*s;
        char piece[8];
        int len = c == '"' || c == '\\' ? snprintf(piece, sizeof piece, "\\%c", c)
                  : c < 0x20            ? snprintf(piece, sizeof piece, "\\u%04x", c)
                                        : snprintf(piece, sizeof piece, "%c", c);
        if (n + (size_t)len >= cap)
            break;
        for (int i = 0; i < len; i++)
            out[n++] = piece[i];
    }
    if (cap > 0)
        out[n] = '\0';
}
