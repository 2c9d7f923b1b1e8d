/* json_text.h - pieces of JSON text for the renderer's reports (stats, --compare): numbers that are
 * null where not finite, and strings escaped. Both write into a caller's buffer, NUL-terminated. */
#ifndef LUCENT_JSON_TEXT_H
#define LUCENT_JSON_TEXT_H

#include <stddef.h>

/* v with 6 significant digits, or null (JSON has no NaN or infinity). */
void json_number(double v, char *out, size_t cap);
/* s as a JSON string's contents (no quotes): quotes, backslashes and control bytes escaped; cut
 * at a whole escape when cap runs out. */
void json_escape(const char *s, char *out, size_t cap);

#endif
