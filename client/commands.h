/* commands.h - the subcommands of lucent. Each takes the arguments after its name and the session
 * options given before it, and returns an exit code (lc_exit) with err filled on failure. */
#ifndef LUCENT_COMMANDS_H
#define LUCENT_COMMANDS_H

#include "cli_error.h"
#include "session.h"

int cmd_render(struct session *s, int argc, char **argv, lc_error *err);
int cmd_meshes(struct session *s, int argc, char **argv, lc_error *err);
int cmd_health(struct session *s, int argc, char **argv, lc_error *err);
int cmd_materials(struct session *s, int argc, char **argv, lc_error *err);

/* The "Options:" block every --help ends with. */
void print_session_options(void);

#endif
