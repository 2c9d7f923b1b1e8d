/* session.h - the options every subcommand takes (--server, --token-file, -v, --help), their
 * environment variables, and the HTTP client they configure. */
#ifndef LUCENT_SESSION_H
#define LUCENT_SESSION_H

#include "cli_args.h"
#include "cli_error.h"
#include "http_client.h"

#define LUCENT_DEFAULT_SERVER "http://127.0.0.1:8080"

struct session {
    const char *server;     /* --server, else LUCENT_SERVER, else the default */
    const char *token_file; /* --token-file, else LUCENT_TOKEN_FILE, else none */
    int verbose;
    int help;
};

extern const struct cli_option session_options[];

void session_init(struct session *s);
/* 1 when the item was a session option (and is now recorded), else 0. */
int session_take(struct session *s, const struct cli_item *item);
/* Reads the token file and sets up the client. */
int session_connect(const struct session *s, struct http_client *c, lc_error *err);

#endif
