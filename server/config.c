/* config.c - lucentd's settings: one table gives each its flag, environment variable, default and help,
 * so --help, the start-up log and the parser cannot disagree. */
#include "config.h"
#include "lucent.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

enum opt_type { OPT_STR, OPT_INT, OPT_U64, OPT_U32, OPT_REAL, OPT_LOG };

struct option_def {
    const char *name;   /* flag --name; environment LUCENTD_NAME with '-' -> '_' */
    enum opt_type type;
    size_t offset;
    size_t size;        /* OPT_STR: capacity */
    const char *def;
    double lo, hi;      /* numeric range */
    const char *help;
};

#define STR(f) OPT_STR, offsetof(struct config, f), sizeof(((struct config *)0)->f)
#define NUM(t, f) t, offsetof(struct config, f), 0

static const struct option_def options[] = {
    {"listen", STR(listen), "127.0.0.1", 0, 0, "address to bind (IPv4 or IPv6 literal); loopback unless told otherwise"},
    {"port", NUM(OPT_INT, port), "8080", 0, 65535, "TCP port (0: any free port, logged at start-up)"},
    {"queue-length", NUM(OPT_INT, queue_length), "16", 1, 100000, "render requests waiting or running; more get 503"},
    {"retry-after", NUM(OPT_INT, retry_after_s), "1", 0, 86400, "seconds sent in Retry-After with 503"},
    {"max-body-bytes", NUM(OPT_U64, max_body_bytes), "67108864", 1024, 1e12, "largest request body (scene or mesh upload)"},
    {"max-body-total", NUM(OPT_U64, max_body_total), "268435456", 1024, 1e13,
     "request bodies held at once, over all connections (declared lengths count in full); past it 503"},
    {"max-width", NUM(OPT_INT, max_width), "2048", 1, 4096, "largest image width"},
    {"max-height", NUM(OPT_INT, max_height), "2048", 1, 4096, "largest image height"},
    {"max-triangles", NUM(OPT_U32, max_triangles), "2000000", 1000, 4000000, "largest mesh (builtin or uploaded)"},
    {"max-samples", NUM(OPT_INT, max_samples), "64", 1, 64, "largest samples per channel"},
    {"max-lights", NUM(OPT_INT, max_lights), "4", 1, 4, "most lights per scene"},
    {"max-projection-size", NUM(OPT_INT, max_projection_size), "1024", 512, 2048,
     "largest projection_size, at least the default 512 (render targets: about 330 bytes per texel squared)"},
    {"render-timeout", NUM(OPT_REAL, render_timeout_s), "60", 0.1, 86400, "seconds a render request may wait and run"},
    {"max-connections", NUM(OPT_INT, max_connections), "256", 4, 60000, "open HTTP connections"},
    {"connection-timeout", NUM(OPT_INT, connection_timeout_s), "30", 1, 86400, "seconds an idle connection is kept"},
    {"max-connections-per-client", NUM(OPT_INT, max_connections_per_client), "32", 0, 60000,
     "open HTTP connections from one client address (0: no limit); more are closed at once"},
    {"request-timeout", NUM(OPT_REAL, request_timeout_s), "120", 0.1, 86400,
     "seconds a client has to send a whole request (headers and body), however steadily it trickles"},
    {"drain-timeout", NUM(OPT_REAL, drain_timeout_s), "30", 0, 86400, "on SIGTERM, seconds queued renders may take"},
    {"store-dir", STR(store_dir), "lucent-store", 0, 0, "directory of the uploaded-mesh store (created if missing)"},
    {"store-key", STR(store_key), "", 0, 0,
     "file of the key that MACs stored meshes, created if missing (default: store.key in the store directory)"},
    {"store-bytes", NUM(OPT_U64, store_bytes), "1073741824", 0, 1e15, "byte budget of the mesh store"},
    {"import-tool", STR(import_tool), "", 0, 0, "mesh importer run in a sandbox (default: lucent-import next to lucentd)"},
    {"import-user", STR(import_user), "nobody", 0, 0,
     "account the mesh importer runs as when lucentd is root (\"\" keeps root; ignored otherwise)"},
    {"import-memory-bytes", NUM(OPT_U64, import_memory_bytes), "2147483648", 1 << 24, 1.8e19,
     "address space of one import (AddressSanitizer builds need terabytes)"},
    {"import-cpu", NUM(OPT_INT, import_cpu_s), "30", 1, 86400, "CPU seconds of one import"},
    {"import-wall", NUM(OPT_INT, import_wall_s), "60", 1, 86400, "wall-clock seconds of one import"},
    {"max-imports", NUM(OPT_INT, max_imports), "2", 1, 64, "mesh uploads imported at once; more get 503"},
    {"cache-bytes", NUM(OPT_U64, cache_bytes), "268435456", 0, 1e13, "encoded images kept in memory (0: no cache)"},
    {"mesh-cache-bytes", NUM(OPT_U64, mesh_cache_bytes), "536870912", 1 << 20, 1e13,
     "meshes kept loaded in the renderer (GPU buffers and CPU copies); a larger mesh gets 413"},
    {"log-level", NUM(OPT_LOG, log_level), "info", 0, 0, "error, warn, info (one line per request) or debug"},
    {"cors-origins", STR(cors_origins), "", 0, 0, "comma-separated origins allowed by CORS, or *; empty: none"},
    {"allowed-hosts", STR(allowed_hosts), "", 0, 0,
     "comma-separated Host names (no port) the API answers for, or *; empty: the loopback names when "
     "listening on loopback, any otherwise"},
    {"token-file", STR(token_file), "", 0, 0, "file holding a bearer token required on all but /healthz, /readyz and the web page"},
    {"backend", STR(backend), "", 0, 0,
     "vulkan, gl (OpenGL 4.5 through EGL) or auto (Vulkan, else OpenGL); empty: $LUCENT_BACKEND, else auto"},
    {"device", STR(device), "", 0, 0,
     "device name substring, Vulkan's or OpenGL's GL_RENDERER (else $LUCENT_DEVICE, else automatic)"},
    {"rate-limit", NUM(OPT_REAL, rate_limit), "0", 0, 1e6,
     "requests a second per client address, averaged (0: no limit); more get 429 (routes open without a token, the probes and the web page, are exempt)"},
    {"rate-burst", NUM(OPT_REAL, rate_burst), "20", 1, 1e6, "requests per client address at once under --rate-limit"},
};
#define OPTION_COUNT (sizeof options / sizeof options[0])

static const char *const log_names[] = {"error", "warn", "info", "debug"};

static int set_option(struct config *cfg, const struct option_def *o, const char *value, const char *origin)
{
    char *dst = (char *)cfg + o->offset;
    if (o->type == OPT_STR) {
        if (strlen(value) >= o->size) {
            fprintf(stderr, "lucentd: %s %s: longer than %zu bytes\n", origin, o->name, o->size - 1);
            return -1;
        }
        memcpy(dst, value, strlen(value) + 1);
        return 0;
    }
    if (o->type == OPT_LOG) {
        for (int i = 0; i < 4; i++)
            if (strcasecmp(value, log_names[i]) == 0) {
                *(enum log_level *)(void *)dst = (enum log_level)i;
                return 0;
            }
        fprintf(stderr, "lucentd: %s %s: expected error, warn, info or debug (got \"%s\")\n", origin, o->name, value);
        return -1;
    }
    char *end = NULL;
    errno = 0;
    double v = strtod(value, &end);
    int integral = o->type != OPT_REAL;
    if (errno || end == value || *end || !isfinite(v) || (integral && v != floor(v)) || v < o->lo || v > o->hi) {
        fprintf(stderr, "lucentd: %s %s: expected %s between %g and %g (got \"%s\")\n", origin, o->name,
                integral ? "an integer" : "a number", o->lo, o->hi, value);
        return -1;
    }
    switch (o->type) {
    case OPT_INT: *(int *)(void *)dst = (int)v; break;
    case OPT_U64: *(uint64_t *)(void *)dst = (uint64_t)v; break;
    case OPT_U32: *(uint32_t *)(void *)dst = (uint32_t)v; break;
    default: *(double *)(void *)dst = v; break;
    }
    return 0;
}

static void env_name(const char *name, char *out, size_t cap)
{
    size_t n = (size_t)snprintf(out, cap, "LUCENTD_%s", name);
    for (size_t i = 8; i < n && i < cap; i++)
        out[i] = out[i] == '-' ? '_' : (char)(out[i] >= 'a' && out[i] <= 'z' ? out[i] - 32 : out[i]);
}

static void print_help(void)
{
    puts("usage: lucentd [--NAME VALUE | --NAME=VALUE]... [--help]\n"
         "Renders translucent objects over HTTP (see server/openapi.json). Every setting is also read\n"
         "from the environment variable shown; flags win over the environment.\n");
    for (size_t i = 0; i < OPTION_COUNT; i++) {
        char env[64];
        env_name(options[i].name, env, sizeof env);
        printf("  --%-20s %-28s default %s\n      %s\n", options[i].name, env,
               options[i].def[0] ? options[i].def : "(empty)", options[i].help);
    }
}

/* The importer is built next to lucentd; found through /proc/self/exe so the working directory does not matter. */
static void default_import_tool(struct config *cfg)
{
    char exe[PATH_MAX];
    ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    if (n <= 0)
        return;
    exe[n] = 0;
    char *slash = strrchr(exe, '/');
    if (slash && (size_t)(slash - exe) + sizeof "/lucent-import" <= sizeof cfg->import_tool)
        snprintf(cfg->import_tool, sizeof cfg->import_tool, "%.*s/lucent-import", (int)(slash - exe), exe);
}

int config_load(struct config *cfg, int argc, char **argv)
{
    memset(cfg, 0, sizeof *cfg);
    for (size_t i = 0; i < OPTION_COUNT; i++)
        if (set_option(cfg, &options[i], options[i].def, "default") != 0)
            return -1;
    for (size_t i = 0; i < OPTION_COUNT; i++) {
        char env[64];
        env_name(options[i].name, env, sizeof env);
        const char *v = getenv(env);
        if (v && set_option(cfg, &options[i], v, env) != 0)
            return -1;
    }
    for (int a = 1; a < argc; a++) {
        if (strcmp(argv[a], "--help") == 0 || strcmp(argv[a], "-h") == 0) {
            print_help();
            return 1;
        }
        const char *arg = argv[a];
        const struct option_def *o = NULL;
        const char *value = NULL;
        for (size_t i = 0; i < OPTION_COUNT && !o; i++) {
            size_t n = strlen(options[i].name);
            if (strncmp(arg, "--", 2) != 0 || strncmp(arg + 2, options[i].name, n) != 0)
                continue;
            if (arg[2 + n] == '=')
                o = &options[i], value = arg + 3 + n;
            else if (arg[2 + n] == 0 && a + 1 < argc)
                o = &options[i], value = argv[++a];
        }
        if (!o) {
            fprintf(stderr, "lucentd: unknown or incomplete argument \"%s\" (see --help)\n", arg);
            return -1;
        }
        if (set_option(cfg, o, value, "flag") != 0)
            return -1;
    }
    if (cfg->backend[0] && !lucent_backend_valid(cfg->backend)) {
        fprintf(stderr, "lucentd: backend must be vulkan, gl or auto (got \"%s\")\n", cfg->backend);
        return -1;
    }
    if (!cfg->import_tool[0])
        default_import_tool(cfg);
    return 0;
}

void config_log(const struct config *cfg)
{
    char line[4096];
    size_t used = 0;
    for (size_t i = 0; i < OPTION_COUNT && used < sizeof line; i++) {
        const struct option_def *o = &options[i];
        const char *p = (const char *)cfg + o->offset;
        int n;
        switch (o->type) {
        case OPT_STR: n = snprintf(line + used, sizeof line - used, " %s=\"%s\"", o->name, p); break;
        case OPT_INT: n = snprintf(line + used, sizeof line - used, " %s=%d", o->name, *(const int *)(const void *)p); break;
        case OPT_U64:
            n = snprintf(line + used, sizeof line - used, " %s=%llu", o->name,
                         (unsigned long long)*(const uint64_t *)(const void *)p);
            break;
        case OPT_U32: n = snprintf(line + used, sizeof line - used, " %s=%u", o->name, *(const uint32_t *)(const void *)p); break;
        case OPT_LOG: n = snprintf(line + used, sizeof line - used, " %s=%s", o->name, log_names[cfg->log_level]); break;
        default: n = snprintf(line + used, sizeof line - used, " %s=%g", o->name, *(const double *)(const void *)p); break;
        }
        if (n < 0)
            break;
        used += (size_t)n;
    }
    fprintf(stderr, "lucentd: settings:%s\n", line);
}
