#!/usr/bin/env python3
"""btview's BehaviorTree.CPP 3 mock (`btview mock --protocol v3`, PyPI
btview 0.2.0: a PublisherZMQ look-alike written apart from btx, with its own
flatbuffer writer and pyzmq sockets), held still until the test's client
listens, then ticked TICKS times, with every transition it publishes
counted: the publisher's own count.

Usage: btview_v3.py SERVER_PORT PUBLISHER_PORT TICK_HZ TICKS OUT.json

Prints READY once bound and waits for a line on its standard input; ticks
TICKS times at TICK_HZ, then holds still (its messages carry no transition)
until a second line comes, writes OUT.json (`[[uid, prev, status], ...]`,
every transition sent, in order) and prints "DONE N".
"""
import json
import sys
import threading
import time

import btview.mock.servers as servers

server_port, publisher_port = int(sys.argv[1]), int(sys.argv[2])
tick_hz, ticks, out = float(sys.argv[3]), int(sys.argv[4]), sys.argv[5]

sent = []
encode = servers.encode_flush_message


def counted(statuses, transitions=()):
    sent.extend([t.uid, t.prev_status, t.status] for t in transitions)
    return encode(statuses, transitions)


servers.encode_flush_message = counted
mock = servers.BtcppV3MockServer(
    server_port=server_port, publisher_port=publisher_port, tick_hz=tick_hz
)
tick = mock.engine.tick
go = threading.Event()
left = [ticks]


def held_tick():
    if go.is_set() and left[0] > 0:
        left[0] -= 1
        return tick()
    return None


mock.engine.tick = held_tick
mock.start()
print("READY", flush=True)
sys.stdin.readline()
go.set()
sys.stdin.readline()
while left[0] > 0:
    time.sleep(0.05)
json.dump(sent, open(out, "w"))
mock.stop()
print(f"DONE {len(sent)}", flush=True)
