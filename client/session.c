/* session.c - the options shared by all subcommands and the HTTP client they describe. They are
 * accepted before or after the subcommand name, so `lucent -v render ...` and `lucent render -v` agree. */
#include "session.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "file_io.h"

enum { S_SERVER = 1000, S_TOKEN_FILE, S_VERBOSE, S_HELP };

const struct cli_option session_options[] = {
    {"server", 0, "URL", "the lucentd to talk to (env LUCENT_SERVER; default " LUCENT_DEFAULT_SERVER ")", S_SERVER},
    {"token-file", 0, "FILE", "send the bearer token in FILE's first line (env LUCENT_TOKEN_FILE)", S_TOKEN_FILE},
    {"verbose", 'v', NULL, "print each request's status, request id, Server-Timing and Lucent-Modelled on stderr", S_VERBOSE},
    {"help", 'h', NULL, "show this help", S_HELP},
    {NULL, 0, NULL, NULL, 0},
};

void session_init(struct session *s)
{
    memset(s, 0, sizeof *s);
    const char *env = getenv("LUCENT_SERVER");
    s->server = env && *env ? env : LUCENT_DEFAULT_SERVER;
    env = getenv("LUCENT_TOKEN_FILE");
    s->token_file = env && *env ? env : NULL;
}

int session_take(struct session *s, const struct cli_item *item)
{
    if (!item->opt)
        return 0;
    switch (item->opt->id) {
    case S_SERVER: s->server = item->value; return 1;
    case S_TOKEN_FILE: s->token_file = item->value; return 1;
    case S_VERBOSE: s->verbose = 1; return 1;
    case S_HELP: s->help = 1; return 1;
    default: return 0;
    }
}

/* The token is the file's first line without surrounding whitespace, as the daemon reads its own. */
static int read_token(const char *path, char **token, lc_error *err)
{
    char *text = NULL;
    size_t len = 0;
    int rc = file_read_all(path, &text, &len, err);
    if (rc != LC_OK) {
        char why[sizeof err->message];
        snprintf(why, sizeof why, "%s", err->message);
        return lc_fail(err, rc, "--token-file: %s", why);
    }
    char *start = text + strspn(text, " \t\r\n");
    size_t n = strcspn(start, "\r\n");
    while (n > 0 && (start[n - 1] == ' ' || start[n - 1] == '\t'))
        n--;
    if (n == 0) {
        free(text);
        return lc_fail(err, LC_E_FILE, "--token-file %s: the first line holds no token", path);
    }
    memmove(text, start, n);
    text[n] = 0;
    *token = text;
    return LC_OK;
}

int session_connect(const struct session *s, struct http_client *c, lc_error *err)
{
    char *token = NULL;
    if (s->token_file) {
        int rc = read_token(s->token_file, &token, err);
        if (rc != LC_OK)
            return rc;
    }
    int rc = http_client_init(c, s->server, token, s->verbose, err);
    free(token);
    return rc;
}
