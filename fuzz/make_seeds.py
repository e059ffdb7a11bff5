#!/usr/bin/env python3
"""Writes seed inputs for fuzz_message_decoder: a ReadRequest body (selector 0), the same
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
