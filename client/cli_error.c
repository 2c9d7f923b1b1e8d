/* cli_error.c - the client's one way to report failure: callers write
 * `return lc_fail(err, LC_E_FILE, "cannot read %s: %s", path, strerror(errno));`. */
#include "cli_error.h"

#include <stdarg.h>
#include <stdio.h>

int lc_fail(lc_error *err, int code, const char *fmt, ...)
{
    err->code = code;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err->message, sizeof err->message, fmt, ap);
    va_end(ap);
    return code;
}
