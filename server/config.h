/* config.h - every lucentd setting, with its flag, environment variable and documented default.
 * Filled once at start-up by config_load; read-only afterwards, so any thread may read it. */
#ifndef LUCENTD_CONFIG_H
#define LUCENTD_CONFIG_H

#include <stddef.h>
#include <stdint.h>

enum log_level { LOG_ERROR = 0, LOG_WARN, LOG_INFO, LOG_DEBUG };

struct config {
    char listen[64];              /* IPv4 or IPv6 literal to bind */
    int port;
    int queue_length;             /* render jobs waiting or running; more get 503 */
    int retry_after_s;            /* Retry-After sent with 503 */
    uint64_t max_body_bytes;      /* scene bodies and mesh uploads */
    uint64_t max_body_total;      /* every request body held at once */
    int max_width, max_height;
    uint32_t max_triangles;       /* builtin tessellation and stored meshes */
    int max_samples;
    int max_lights;
    int max_projection_size;
    double render_timeout_s;      /* from accepting the request to the image being ready */
    int max_connections;
    int max_connections_per_client; /* per client address; 0: no limit */
    double request_timeout_s;     /* to send a whole request, headers and body */
    int connection_timeout_s;     /* idle connections (MHD); suspended ones use render_timeout_s */
    double drain_timeout_s;       /* on SIGTERM: how long queued and running renders may take */
    char store_dir[512];
    char store_key[512];          /* the store's MAC key; "" is <store_dir>/store.key */
    uint64_t store_bytes;
    char import_tool[512];        /* the sandboxed importer executable (lucent-import) */
    char import_user[64];         /* the account it runs as when lucentd is root */
    uint64_t import_memory_bytes;
    int import_cpu_s;
    int import_wall_s;
    int max_imports;              /* uploads imported at once; more get 503 */
    uint64_t cache_bytes;         /* encoded images kept in memory; 0 disables the cache */
    uint64_t mesh_cache_bytes;    /* meshes kept loaded in the renderer */
    enum log_level log_level;
    char cors_origins[1024];      /* comma-separated exact origins, or "*"; empty: no CORS headers */
    char allowed_hosts[1024];     /* Host names the API answers for, or "*"; empty: loopback names on loopback */
    char token_file[512];         /* bearer token required when set */
    char backend[16];             /* vulkan, gl or auto; empty: $LUCENT_BACKEND, else auto */
    char device[128];             /* device name substring; empty: automatic */
    double rate_limit;            /* requests a second per client address; 0: no limit */
    double rate_burst;            /* requests at once per client address */
};

/* Fills cfg from defaults, then LUCENTD_* environment variables, then argv flags (later wins).
 * Returns 0 to run, 1 when --help was printed, -1 on a bad setting (message on stderr). */
int config_load(struct config *cfg, int argc, char **argv);
/* Logs every setting at start-up, one line. */
void config_log(const struct config *cfg);

#endif
