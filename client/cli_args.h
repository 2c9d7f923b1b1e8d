/* cli_args.h - the command line: option tables, a getopt-like walk over argv that accepts --name VALUE,
 * --name=VALUE and -x VALUE anywhere, and parsers for the value syntaxes (numbers, vectors, WxH). */
#ifndef LUCENT_CLI_ARGS_H
#define LUCENT_CLI_ARGS_H

#include "cli_error.h"

struct cli_option {
    const char *name;    /* long name without the dashes */
    char short_name;     /* 0 when none */
    const char *arg;     /* the value's placeholder in --help; NULL for a flag without a value */
    const char *help;
    int id;
};

/* One walk over argv; options come from any of up to three NULL-name-terminated tables. */
struct cli_parser {
    int argc;
    char **argv;
    int next;
    int no_more_options; /* after "--" */
    const struct cli_option *tables[3];
    const char *command; /* for messages: "render", or "" before the subcommand */
};

struct cli_item {
    const struct cli_option *opt; /* NULL for a positional argument */
    const char *value;            /* the option's value, or the positional argument */
};

void cli_parser_init(struct cli_parser *p, int argc, char **argv, const char *command,
                     const struct cli_option *t1, const struct cli_option *t2, const struct cli_option *t3);
/* Returns 1 with *item filled, 0 at the end, -1 on a usage error (err filled). */
int cli_next(struct cli_parser *p, struct cli_item *item, lc_error *err);

void cli_print_options(const struct cli_option *table);

/* Value parsers: LC_OK or LC_E_USAGE with a message naming the option. */
int cli_number(const char *opt, const char *s, double *out, lc_error *err);
int cli_int(const char *opt, const char *s, long min, long max, long *out, lc_error *err);
int cli_vector(const char *opt, const char *s, int n, double *out, lc_error *err);
int cli_size(const char *opt, const char *s, long *w, long *h, lc_error *err);

#endif
