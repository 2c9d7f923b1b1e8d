/* server_problem.h - turns an answer the client did not want (an RFC 9457 problem from lucentd, or
 * anything else) into the one-line message the user sees. */
#ifndef LUCENT_SERVER_PROBLEM_H
#define LUCENT_SERVER_PROBLEM_H

#include "cli_error.h"
#include "http_client.h"

/* "400 Invalid request: material.sigma_a[1]: must be ..." from problem+json (plus the retry delay of
 * a 503), else the status and the start of the body. Returns LC_E_SERVER. */
int server_problem(const struct http_response *rs, lc_error *err);

#endif
