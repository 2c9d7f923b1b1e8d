/* error.c - the one way liblucent reports failure: a status code plus a message naming the field.
 * Callers write `return lucent_fail(err, LUCENT_E_INVALID, "width", "must be ...");`. */
#include "lucent.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

lucent_status lucent_fail(lucent_error *err, lucent_status status, const char *field,
                          const char *fmt, ...)
{
    if (!err)
        return status;
    err->status = status;
    snprintf(err->field, sizeof err->field, "%s", field ? field : "");
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err->message, sizeof err->message, fmt, ap);
    va_end(ap);
    return status;
}

const char *lucent_status_name(lucent_status s)
{
    switch (s) {
    case LUCENT_OK: return "ok";
    case LUCENT_E_INVALID: return "invalid";
    case LUCENT_E_MESH: return "mesh";
    case LUCENT_E_LIMIT: return "limit";
    case LUCENT_E_IO: return "io";
    case LUCENT_E_NOMEM: return "nomem";
    case LUCENT_E_GPU: return "gpu";
    case LUCENT_E_INTERNAL: return "internal";
    case LUCENT_E_CANCELLED: return "cancelled";
    case LUCENT_E_DEVICE_LOST: return "device-lost";
    case LUCENT_E_NOSPACE: return "nospace";
    }
    return "unknown";
}

lucent_status lucent_io_status(int errnum)
{
    return errnum == ENOSPC || errnum == EDQUOT ? LUCENT_E_NOSPACE : LUCENT_E_IO;
}
