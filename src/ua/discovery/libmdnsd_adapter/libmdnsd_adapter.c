#include "libmdnsd_adapter.h"

#include <arpa/inet.h>
#include <libmdnsd/mdnsd.h>
#include <stdlib.h>
#include <string.h>

struct mdns_adapter {
    mdns_daemon_t* daemon;
    struct message in;                    /* libmdnsd's parse state (~70 KiB) */
    struct message out;                   /* and its output message */
    unsigned char packet[MAX_PACKET_LEN]; /* zero-padded input: its parser has no length */
};

mdns_adapter* mdns_adapter_new(int frame) {
    mdns_adapter* a = calloc(1, sizeof *a);
    if (a == NULL) return NULL;
    a->daemon = mdnsd_new(QCLASS_IN, frame);
    if (a->daemon == NULL) {
        free(a);
        return NULL;
    }
    return a;
}

void mdns_adapter_free(mdns_adapter* a) {
    if (a == NULL) return;
    mdnsd_free(a->daemon);
    free(a);
}

mdns_adapter_record* mdns_adapter_shared(mdns_adapter* a, const char* name, int type,
                                         unsigned long ttl) {
    return (mdns_adapter_record*)mdnsd_shared(a->daemon, name, (unsigned short)type, ttl);
}

void mdns_adapter_set_ip(mdns_adapter* a, mdns_adapter_record* r, uint32_t ip) {
    struct in_addr addr;
    addr.s_addr = ip;
    mdnsd_set_ip(a->daemon, (mdns_record_t*)r, addr);
}

void mdns_adapter_set_host(mdns_adapter* a, mdns_adapter_record* r, const char* host) {
    mdnsd_set_host(a->daemon, (mdns_record_t*)r, host);
}

void mdns_adapter_set_srv(mdns_adapter* a, mdns_adapter_record* r, unsigned short port,
                          const char* host) {
    /* libmdnsd copies the name (strdup) but declares it non-const. */
    mdnsd_set_srv(a->daemon, (mdns_record_t*)r, 0, 0, port, (char*)host);
}

void mdns_adapter_set_raw(mdns_adapter* a, mdns_adapter_record* r, const char* data,
                          unsigned short len) {
    mdnsd_set_raw(a->daemon, (mdns_record_t*)r, data, len);
}

void mdns_adapter_done(mdns_adapter* a, mdns_adapter_record* r) {
    mdnsd_done(a->daemon, (mdns_record_t*)r);
}

void mdns_adapter_shutdown(mdns_adapter* a) {
    mdnsd_shutdown(a->daemon);
}

void mdns_adapter_in(mdns_adapter* a, const unsigned char* data, size_t len, uint32_t ip,
                     unsigned short port) {
    struct in_addr from;
    if (len > MDNS_ADAPTER_MAX_INPUT) return;
    memset(a->packet, 0, MDNS_ADAPTER_MAX_INPUT + 16);
    memcpy(a->packet, data, len);
    memset(&a->in, 0, sizeof a->in);
    message_parse(&a->in, a->packet);
    from.s_addr = ip;
    mdnsd_in(a->daemon, &a->in, from, port);
}

size_t mdns_adapter_out(mdns_adapter* a, const unsigned char** data, int* multicast, uint32_t* ip,
                        unsigned short* port) {
    struct in_addr to;
    unsigned short p = 0;
    to.s_addr = 0;
    if (mdnsd_out(a->daemon, &a->out, &to, &p) <= 0) return 0;
    *data = message_packet(&a->out);
    *multicast = to.s_addr == inet_addr("224.0.0.251");
    *ip = to.s_addr;
    *port = p;
    return (size_t)message_packet_len(&a->out);
}

long long mdns_adapter_sleep_us(mdns_adapter* a) {
    const struct timeval* tv = mdnsd_sleep(a->daemon);
    if (tv == NULL) return 0;
    return (long long)tv->tv_sec * 1000000LL + tv->tv_usec;
}
