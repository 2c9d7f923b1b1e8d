/* cli_error.h - how the lucent client reports failure: an exit code (the documented classes below)
 * plus one message a user can act on, printed once by main(). */
#ifndef LUCENT_CLI_ERROR_H
#define LUCENT_CLI_ERROR_H

enum lc_exit {
    LC_OK = 0,
    LC_E_SERVER = 1,  /* the server answered with an error (or with something that is not the answer) */
    LC_E_USAGE = 2,   /* bad command line or scene document */
    LC_E_CONNECT = 3, /* the server could not be reached, or the connection failed */
    LC_E_FILE = 4,    /* a local file could not be read or written */
    LC_E_INTERNAL = 5 /* out of memory or a library failure inside the client */
};

typedef struct lc_error {
    int code;
    char message[2048];
} lc_error;

int lc_fail(lc_error *err, int code, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

#endif
