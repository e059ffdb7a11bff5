/* Debian's libmdnsd-dev headers include "config.h" from the library's own build, which the
 * package does not ship. This stands in for it with what the headers test for. Only
 * libmdnsd_adapter.c has this directory on its include path. */
#pragma once
#define HAVE_NETINET_IN_H 1
#define HAVE_SYS_SOCKET_H 1
