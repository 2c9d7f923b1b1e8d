/* lucent.c - the lucent command-line client of the lucentd render daemon: global options, the
 * subcommand table, and the one place an error is printed and turned into the exit status. */
#include <curl/curl.h>
#include <stdio.h>
#include <string.h>

#include "commands.h"

static const struct {
    const char *name;
    int (*run)(struct session *s, int argc, char **argv, lc_error *err);
    const char *summary;
} commands[] = {
    {"render", cmd_render, "render a scene to PNG or EXR (lucent render --help lists the scene flags)"},
    {"meshes", cmd_meshes, "upload, show or delete meshes on the server"},
    {"health", cmd_health, "is the server alive and ready to render?"},
    {"materials", cmd_materials, "the material presets and their coefficients"},
};

void print_session_options(void)
{
    printf("\nCommon options (before or after the subcommand):\n");
    cli_print_options(session_options);
}

static void usage(void)
{
    printf("Usage: lucent [--server URL] [--token-file FILE] [-v] COMMAND [ARGS]\n"
           "\n"
           "Client of the lucentd render daemon (translucent objects, five-view image-space subsurface scattering).\n"
           "\nCommands:\n");
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++)
        printf("  %-10s %s\n", commands[i].name, commands[i].summary);
    print_session_options();
    printf("\nExit status: 0 done; 1 the server answered with an error (its message is printed); 2 bad usage;\n"
           "3 the server could not be reached; 4 a local file could not be read or written; 5 out of memory.\n"
           "Environment: LUCENT_SERVER, LUCENT_TOKEN_FILE.\n");
}

int main(int argc, char **argv)
{
    struct session s;
    lc_error err = {0};
    struct cli_parser p;
    struct cli_item it;
    int n, rc = LC_OK;
    session_init(&s);
    cli_parser_init(&p, argc - 1, argv + 1, "", session_options, NULL, NULL);
    /* Session options before the command name; the command parses the rest. */
    while ((n = cli_next(&p, &it, &err)) == 1 && session_take(&s, &it))
        ;
    if (n < 0) {
        rc = err.code;
        goto done;
    }
    if (n == 0) {
        if (s.help) {
            usage();
        } else {
            rc = lc_fail(&err, LC_E_USAGE, "a command is required: render, meshes, health or materials (lucent --help)");
        }
        goto done;
    }
    size_t i = 0;
    while (i < sizeof commands / sizeof commands[0] && strcmp(commands[i].name, it.value) != 0)
        i++;
    if (i == sizeof commands / sizeof commands[0]) {
        rc = lc_fail(&err, LC_E_USAGE, "unknown command '%s': expected render, meshes, health or materials (lucent --help)",
                     it.value);
        goto done;
    }
    if (curl_global_init(CURL_GLOBAL_DEFAULT) != CURLE_OK) {
        rc = lc_fail(&err, LC_E_INTERNAL, "libcurl failed to initialise");
        goto done;
    }
    rc = commands[i].run(&s, argc - 1 - p.next, argv + 1 + p.next, &err);
    curl_global_cleanup();
done:
    if (rc != LC_OK)
        fprintf(stderr, "lucent: %s\n", err.message);
    return rc;
}
