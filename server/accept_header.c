/* accept_header.c - parses Accept item by item over the header's own bytes: no item is cut at a
 * buffer's size, and only a parameter named exactly q is a q-value ("sq=0" is not). */
#include "accept_header.h"

#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* [*start, *end) without spaces and tabs at either end. */
static void trim(const char **start, const char **end)
{
    while (*start < *end && (**start == ' ' || **start == '\t'))
        (*start)++;
    while (*end > *start && ((*end)[-1] == ' ' || (*end)[-1] == '\t'))
        (*end)--;
}

static int range_is(const char *range, size_t len, const char *name)
{
    return strlen(name) == len && strncasecmp(range, name, len) == 0;
}

/* The q parameter among ";name=value" pairs in [p, end); 1 when there is none. */
static double q_of(const char *p, const char *end)
{
    while (p < end) {
        const char *next = memchr(p, ';', (size_t)(end - p));
        if (!next)
            next = end;
        const char *name = p, *eq = memchr(p, '=', (size_t)(next - p));
        const char *name_end = eq ? eq : next;
        trim(&name, &name_end);
        if (eq && name_end - name == 1 && (*name == 'q' || *name == 'Q')) {
            char value[16];
            const char *v = eq + 1, *v_end = next;
            trim(&v, &v_end);
            size_t n = (size_t)(v_end - v) < sizeof value - 1 ? (size_t)(v_end - v) : sizeof value - 1;
            memcpy(value, v, n);
            value[n] = '\0';
            double q = strtod(value, NULL);
            return q > 0 ? (q < 1 ? q : 1) : 0;
        }
        p = next + (next < end);
    }
    return 1;
}

double accept_q(const char *accept, const char *type)
{
    double best = 0;
    int best_specificity = -1;
    for (const char *p = accept; *p;) {
        size_t len = strcspn(p, ",");
        const char *item_end = p + len, *semi = memchr(p, ';', len);
        const char *range = p, *range_end = semi ? semi : item_end;
        trim(&range, &range_end);
        size_t n = (size_t)(range_end - range);
        int specificity = range_is(range, n, type)        ? 2
                          : range_is(range, n, "image/*") ? 1
                          : range_is(range, n, "*/*")     ? 0
                                                          : -1;
        if (specificity > best_specificity) {
            best_specificity = specificity;
            best = semi ? q_of(semi + 1, item_end) : 1;
        }
        p = item_end + (*item_end == ',');
    }
    return best;
}
