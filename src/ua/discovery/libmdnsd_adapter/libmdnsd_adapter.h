/* libmdnsd_adapter: the part of libmdnsd that MdnsResponder uses, behind a C interface that
 * C++ can include. libmdnsd's own headers use `class` as a parameter name, so they compile
 * only as C; and its parser takes no length, so the adapter owns the zero-padded buffers it
 * needs and takes explicit lengths instead.
 *
 * Addresses are IPv4 in network byte order. Record handles stay valid until mdns_adapter_done()
 * (libmdnsd frees a record once its goodbye is sent), mdns_adapter_shutdown() or _free(). */
#ifndef SKILLCELL_LIBMDNSD_ADAPTER_H
#define SKILLCELL_LIBMDNSD_ADAPTER_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct mdns_adapter mdns_adapter;
typedef struct mdns_adapter_record mdns_adapter_record;

enum { MDNS_ADAPTER_A = 1, MDNS_ADAPTER_PTR = 12, MDNS_ADAPTER_TXT = 16, MDNS_ADAPTER_SRV = 33 };
/* Largest input mdns_adapter_in() accepts. */
enum { MDNS_ADAPTER_MAX_INPUT = 4096 };

/* frame: the largest datagram libmdnsd may build. NULL when out of memory. */
mdns_adapter* mdns_adapter_new(int frame);
void mdns_adapter_free(mdns_adapter* a);

/* A shared record (no probing: the names are unique by construction), published at once. */
mdns_adapter_record* mdns_adapter_shared(mdns_adapter* a, const char* name, int type,
                                         unsigned long ttl);
void mdns_adapter_set_ip(mdns_adapter* a, mdns_adapter_record* r, uint32_t ip);
void mdns_adapter_set_host(mdns_adapter* a, mdns_adapter_record* r, const char* host);
void mdns_adapter_set_srv(mdns_adapter* a, mdns_adapter_record* r, unsigned short port,
                          const char* host);
void mdns_adapter_set_raw(mdns_adapter* a, mdns_adapter_record* r, const char* data,
                          unsigned short len);
/* Withdraws a record: its goodbye (TTL 0) goes out with the next datagrams. */
void mdns_adapter_done(mdns_adapter* a, mdns_adapter_record* r);
/* Goodbyes for every record. */
void mdns_adapter_shutdown(mdns_adapter* a);

/* One received query (already validated; len <= MDNS_ADAPTER_MAX_INPUT, else ignored);
 * port in host order. */
void mdns_adapter_in(mdns_adapter* a, const unsigned char* data, size_t len, uint32_t ip,
                     unsigned short port);
/* The next datagram to send: its length (0: nothing to send now); *data stays valid until
 * the next call. *multicast is 1 for the mDNS group, else *ip / *port (host order) say where. */
size_t mdns_adapter_out(mdns_adapter* a, const unsigned char** data, int* multicast, uint32_t* ip,
                        unsigned short* port);
/* Microseconds until mdns_adapter_out() has something again. */
long long mdns_adapter_sleep_us(mdns_adapter* a);

#ifdef __cplusplus
}
#endif

#endif
