/* cli_args.c - walks argv against option tables and parses option values. Written by hand because
 * getopt_long is not POSIX, and so every message can name the subcommand and the option. */
#include "cli_args.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void cli_parser_init(struct cli_parser *p, int argc, char **argv, const char *command,
                     const struct cli_option *t1, const struct cli_option *t2, const struct cli_option *t3)
{
    memset(p, 0, sizeof *p);
    p->argc = argc;
    p->argv = argv;
    p->command = command;
    p->tables[0] = t1;
    p->tables[1] = t2;
    p->tables[2] = t3;
}

static const struct cli_option *find_long(const struct cli_parser *p, const char *name, size_t len)
{
    for (int t = 0; t < 3; t++)
        for (const struct cli_option *o = p->tables[t]; o && o->name; o++)
            if (strlen(o->name) == len && strncmp(o->name, name, len) == 0)
                return o;
    return NULL;
}

static const struct cli_option *find_short(const struct cli_parser *p, char c)
{
    for (int t = 0; t < 3; t++)
        for (const struct cli_option *o = p->tables[t]; o && o->name; o++)
            if (o->short_name && o->short_name == c)
                return o;
    return NULL;
}

/* lc_fail for cli_next, whose positive returns mean "an item". */
static int usage(lc_error *err, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
static int usage(lc_error *err, const char *fmt, ...)
{
    err->code = LC_E_USAGE;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err->message, sizeof err->message, fmt, ap);
    va_end(ap);
    return -1;
}

int cli_next(struct cli_parser *p, struct cli_item *item, lc_error *err)
{
    if (p->next >= p->argc)
        return 0;
    const char *arg = p->argv[p->next++];
    item->opt = NULL;
    item->value = arg;
    if (p->no_more_options || arg[0] != '-' || arg[1] == 0)
        return 1;
    if (strcmp(arg, "--") == 0) {
        p->no_more_options = 1;
        return cli_next(p, item, err);
    }
    const struct cli_option *o;
    const char *inline_value = NULL;
    if (arg[1] == '-') {
        const char *eq = strchr(arg + 2, '=');
        size_t len = eq ? (size_t)(eq - arg - 2) : strlen(arg + 2);
        o = find_long(p, arg + 2, len);
        if (eq)
            inline_value = eq + 1;
    } else {
        o = arg[2] == 0 ? find_short(p, arg[1]) : NULL;
    }
    if (!o)
        return usage(err, "%s%sunknown option '%s' (see lucent%s%s --help)", p->command, *p->command ? ": " : "", arg,
                     *p->command ? " " : "", p->command);
    item->opt = o;
    item->value = NULL;
    if (!o->arg) {
        if (inline_value)
            return usage(err, "%s%s--%s takes no value", p->command, *p->command ? ": " : "", o->name);
        return 1;
    }
    if (inline_value) {
        item->value = inline_value;
        return 1;
    }
    if (p->next >= p->argc)
        return usage(err, "%s%s--%s needs a value: %s", p->command, *p->command ? ": " : "", o->name, o->arg);
    /* The value is taken as is, even when it starts with '-': vectors like -1,0,0 are common. */
    item->value = p->argv[p->next++];
    return 1;
}

void cli_print_options(const struct cli_option *table)
{
    for (const struct cli_option *o = table; o->name; o++) {
        char head[64];
        if (o->short_name)
            snprintf(head, sizeof head, "-%c, --%s%s%s", o->short_name, o->name, o->arg ? " " : "",
                     o->arg ? o->arg : "");
        else
            snprintf(head, sizeof head, "    --%s%s%s", o->name, o->arg ? " " : "", o->arg ? o->arg : "");
        printf("  %-32s %s\n", head, o->help);
    }
}

int cli_number(const char *opt, const char *s, double *out, lc_error *err)
{
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (end == s || *end || errno == ERANGE || !isfinite(v))
        return lc_fail(err, LC_E_USAGE, "%s: expected a number, got '%s'", opt, s);
    *out = v;
    return LC_OK;
}

int cli_int(const char *opt, const char *s, long min, long max, long *out, lc_error *err)
{
    char *end;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (end == s || *end || errno == ERANGE || v < min || v > max)
        return lc_fail(err, LC_E_USAGE, "%s: expected an integer %ld..%ld, got '%s'", opt, min, max, s);
    *out = v;
    return LC_OK;
}

int cli_vector(const char *opt, const char *s, int n, double *out, lc_error *err)
{
    const char *p = s;
    for (int i = 0; i < n; i++) {
        char *end;
        errno = 0;
        out[i] = strtod(p, &end);
        int last = i == n - 1;
        if (end == p || errno == ERANGE || !isfinite(out[i]) || (last ? *end != 0 : *end != ','))
            return lc_fail(err, LC_E_USAGE, "%s: expected %d comma-separated numbers, got '%s'", opt, n, s);
        p = end + 1;
    }
    return LC_OK;
}

int cli_size(const char *opt, const char *s, long *w, long *h, lc_error *err)
{
    char *end;
    errno = 0;
    long a = strtol(s, &end, 10);
    if (end == s || (*end != 'x' && *end != 'X') || a < 1 || errno == ERANGE)
        return lc_fail(err, LC_E_USAGE, "%s: expected WIDTHxHEIGHT such as 256x256, got '%s'", opt, s);
    const char *p = end + 1;
    long b = strtol(p, &end, 10);
    if (end == p || *end || b < 1 || errno == ERANGE || a > 1000000 || b > 1000000)
        return lc_fail(err, LC_E_USAGE, "%s: expected WIDTHxHEIGHT such as 256x256, got '%s'", opt, s);
    *w = a;
    *h = b;
    return LC_OK;
}
