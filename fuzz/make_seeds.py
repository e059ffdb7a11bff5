#!/usr/bin/env python3
"""Writes seed inputs for the fuzz targets. fuzz_message_decoder: a ReadRequest body (selector 0), the same
request as a MSG frame on channel 1 / token 1 (selector 1), and a Hello (selector 2)."""
import os
import struct

here = os.path.dirname(os.path.abspath(__file__))
out = os.path.join(here, "corpus", "fuzz_message_decoder")
os.makedirs(out, exist_ok=True)

null_string = struct.pack("<i", -1)
request_header = (b"\x00\x00" + bytes(8) + struct.pack("<IIi", 1, 0, -1) + struct.pack("<I", 0)
                  + b"\x00\x00\x00")
read_value_id = b"\x00\x55" + struct.pack("<I", 13) + null_string + b"\x00\x00" + null_string
read_request = (b"\x01\x00\x77\x02" + request_header + struct.pack("<di", 0.0, 2)
                + struct.pack("<i", 1) + read_value_id)
body = struct.pack("<IIII", 1, 1, 1, 1) + read_request  # channel, token, sequence, request id
msg = b"MSGF" + struct.pack("<I", 8 + len(body)) + body
url = b"opc.tcp://localhost:4840"
hello = struct.pack("<IIIIIi", 0, 65535, 65535, 0, 0, len(url)) + url

for name, data in {"read_body": b"\x00" + read_request, "read_frame": b"\x01" + msg,
                   "hello": b"\x02" + hello}.items():
    with open(os.path.join(out, name), "wb") as f:
        f.write(data)

# fuzz_mdns_datagram: an mDNS query for the OPC UA service and an announcement of one.
def dns_name(name):
    return b"".join(bytes([len(p)]) + p.encode() for p in name.split(".")) + b"\x00"

def rr(name, rtype, ttl, rdata):
    return dns_name(name) + struct.pack(">HHIH", rtype, 1, ttl, len(rdata)) + rdata

mdns_out = os.path.join(here, "corpus", "fuzz_mdns_datagram")
os.makedirs(mdns_out, exist_ok=True)
query = struct.pack(">HHHHHH", 0, 0, 1, 0, 0, 0) + dns_name("_opcua-tcp._tcp.local") + struct.pack(">HH", 12, 1)
instance = "pump._opcua-tcp._tcp.local"
txt = b"".join(bytes([len(s)]) + s for s in (b"path=/", b"caps=LDS"))
answer = (struct.pack(">HHHHHH", 0, 0x8400, 0, 4, 0, 0)
          + rr("_opcua-tcp._tcp.local", 12, 120, dns_name(instance))
          + rr(instance, 33, 120, struct.pack(">HHH", 0, 0, 4840) + dns_name("host.local"))
          + rr(instance, 16, 120, txt)
          + rr("host.local", 1, 120, bytes([127, 0, 0, 1])))
for name, data in {"query": query, "announcement": answer}.items():
    with open(os.path.join(mdns_out, name), "wb") as f:
        f.write(data)

# fuzz_session_services: requests in a session, each [service][length LE16][request after its
# RequestHeader]; the service numbers are the index in session_services_fuzzer.cpp's kServices.
READ, WRITE, BROWSE, CALL, CREATE_SUBSCRIPTION, CREATE_MONITORED_ITEMS, PUBLISH = 0, 1, 2, 7, 8, 12, 16


def request(service, body):
    return bytes([service]) + struct.pack("<H", len(body)) + body


def numeric(i):  # a NodeId in ns 0: two-byte form below 256, else four-byte
    return bytes([0, i]) if i < 256 else b"\x01\x00" + struct.pack("<H", i)


def read_value_id(node, attribute=13):
    return numeric(node) + struct.pack("<I", attribute) + null_string + b"\x00\x00" + null_string


session_out = os.path.join(here, "corpus", "fuzz_session_services")
os.makedirs(session_out, exist_ok=True)
read = struct.pack("<di", 0.0, 2) + struct.pack("<i", 2) + read_value_id(2255) + read_value_id(2258)
browse = (b"\x00\x00" + bytes(8) + struct.pack("<I", 0)  # no view
          + struct.pack("<I", 0) + struct.pack("<i", 1)
          + numeric(85) + struct.pack("<i", 0) + numeric(33) + b"\x01" + struct.pack("<II", 0, 63))
write = (struct.pack("<i", 1) + numeric(2255) + struct.pack("<I", 13) + null_string
         + b"\x01" + b"\x06" + struct.pack("<i", 7))  # DataValue with an Int32 value
subscription = struct.pack("<dIIIB", 20.0, 600, 10, 0, 1) + b"\x00"
monitored = (struct.pack("<Ii", 1, 2) + struct.pack("<i", 1) + read_value_id(2258)
             + struct.pack("<i", 2) + struct.pack("<Id", 1, 0.0) + b"\x00\x00\x00"
             + struct.pack("<I", 4) + b"\x01")
publish = struct.pack("<i", 0)
call = (struct.pack("<i", 1) + numeric(2253) + b"\x01\x00" + struct.pack("<H", 11492)
        + struct.pack("<i", 1) + b"\x07" + struct.pack("<I", 1))  # GetMonitoredItems(1)
seeds = {
    "read": request(READ, read),
    "browse": request(BROWSE, browse),
    "write": request(WRITE, write),
    "call": request(CALL, call),
    "subscribe_and_publish": request(CREATE_SUBSCRIPTION, subscription)
    + request(CREATE_MONITORED_ITEMS, monitored) + request(PUBLISH, publish)
    + request(PUBLISH, publish),
}
for name, data in seeds.items():
    with open(os.path.join(session_out, name), "wb") as f:
        f.write(data)


# fuzz_http_endpoint: HTTP requests as a client sends them to the KB's endpoint, as each of
# its users (the harness's table: observer/observer-pw, engineer/engineer-pw) and as nobody.
import base64
import urllib.parse

http_out = os.path.join(here, "corpus", "fuzz_http_endpoint")
os.makedirs(http_out, exist_ok=True)


def basic(user):
    return "Authorization: Basic " + base64.b64encode(f"{user}:{user}-pw".encode()).decode() + "\r\n"


def http(method, target, user=None, content_type=None, body=b"", extra=""):
    head = f"{method} {target} HTTP/1.1\r\nHost: localhost\r\n" + (basic(user) if user else "")
    if content_type:
        head += f"Content-Type: {content_type}\r\nContent-Length: {len(body)}\r\n"
    return (head + extra + "\r\n").encode() + body


select = "PREFIX ua: <http://opcfoundation.org/UA/> SELECT ?g WHERE { GRAPH ?g { ?s ?p ?o } } LIMIT 3"
insert = "INSERT DATA { GRAPH <urn:x> { <urn:a> <urn:b> <urn:c> } }"
turtle = b"@prefix ex: <http://example.org/> .\nex:a ex:b ex:c ; ex:d \"text\"@en , 42 .\n"
seeds = {
    "get_query": http("GET", "/sparql?query=" + urllib.parse.quote(select), "observer",
                      extra="Accept: application/sparql-results+json\r\n"),
    "get_graphs": http("GET", "/graphs", "observer"),
    "post_form_query": http("POST", "/sparql", "observer", "application/x-www-form-urlencoded",
                            ("query=" + urllib.parse.quote(select)).encode()),
    "post_form_update_as_query": http("POST", "/sparql", "observer",
                                      "application/x-www-form-urlencoded",
                                      ("query=" + urllib.parse.quote(insert)).encode()),
    "post_update_engineer": http("POST", "/sparql", "engineer", "application/sparql-update",
                                 insert.encode()),
    "post_sparql_query": http("POST", "/sparql", "engineer", "application/sparql-query",
                              select.encode()),
    "put_graph": http("PUT", "/graphs?graph=" + urllib.parse.quote("http://example.org/g"),
                      "engineer", "text/turtle", turtle),
    "chunked_update": (f"POST /sparql HTTP/1.1\r\nHost: localhost\r\n{basic('engineer')}"
                       "Content-Type: application/sparql-update\r\n"
                       "Transfer-Encoding: chunked\r\n\r\n").encode()
                      + f"{len(insert):x}\r\n{insert}\r\n0\r\n\r\n".encode(),
    "anonymous": http("GET", "/sparql?query=ASK%7B%7D"),
    "wrong_password": http("GET", "/graphs", extra="Authorization: Basic "
                           + base64.b64encode(b"engineer:nope").decode() + "\r\n"),
    "two_requests": http("GET", "/graphs", "observer") + http("DELETE", "/sparql", "engineer"),
}
for name, data in seeds.items():
    with open(os.path.join(http_out, name), "wb") as f:
        f.write(data)
