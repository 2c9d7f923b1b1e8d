/* accept_header.h - content negotiation: the q-value an Accept header gives a media type. */
#ifndef LUCENTD_ACCEPT_HEADER_H
#define LUCENTD_ACCEPT_HEADER_H

/* The q-value of type in accept (RFC 9110 12.5.1): the most specific matching range decides (the
 * type itself, then "image/" with a star, then a star for both); 0 when none matches. Items of any
 * length. */
double accept_q(const char *accept, const char *type);

#endif
