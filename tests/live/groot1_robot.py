#!/usr/bin/env python3
"""A BehaviorTree.CPP 3 robot for btx's live tests: it replays a run the
real library recorded (a v3 FileLogger `.fbl`, from ../shared/fixtures/btcpp)
over the wire protocol of the library's PublisherZMQ
(behaviortree_cpp_v3, src/loggers/bt_zmq_publisher.cpp):

- a REP socket on SERVER_PORT answers any request with the tree flatbuffer
  (the bytes the .fbl holds after its size field);
- a PUB socket on PUBLISHER_PORT sends one message per batch:
  `u32 n | n bytes of (u16 uid, i8 status), every node in depth-first order
  | u32 k | k records of 12 bytes`. As flush() does, the statuses are those
  when the previous message was sent (it copies its status buffer, then
  builds the next one), all IDLE for the first; the records are the .fbl's,
  byte for byte (the FileLogger and the publisher serialize a transition
  alike). The publisher sends a batch 40 ms after its first transition
  (25 messages a second, its default), so a batch here is the records
  whose timestamps fall within 40 ms of its first.

The nodes' uids and order come from btview's flatbuffer reader (the PyPI
package btview, written apart from btx); pyzmq (libzmq) does the sockets.

Usage: groot1_robot.py RUN.fbl SERVER_PORT PUBLISHER_PORT [GAP_MS | flood:SECS]

With flood:SECS, a hostile publisher: for SECS seconds it sends, as fast as
it can, messages of 1,000 records of the run's first node starting and going back
to IDLE, all with one timestamp (a tick that never ends), then ends as above.

Prints READY once bound and waits for a line on its standard input (the
test says when its client listens); sends the batches GAP_MS apart (default
5), serves one more second, prints "DONE N" (N transitions sent) and exits,
which closes both sockets.
"""
import struct
import sys
import threading
import time

import zmq
from btview.protocol.bt_logger_fb import read_behavior_tree


def read_fbl(path):
    data = open(path, "rb").read()
    (size,) = struct.unpack_from("<I", data, 0)
    tree = data[4 : 4 + size]
    body = data[4 + size :]
    records = [body[i : i + 12] for i in range(0, len(body) - len(body) % 12, 12)]
    return tree, records


def depth_first(tree):
    view = read_behavior_tree(tree)
    children = {n.uid: n.children_uid for n in view.nodes}
    order = []

    def visit(uid):
        order.append(uid)
        for c in children.get(uid, []):
            visit(c)

    visit(view.root_uid)
    return order


def batches(records, window_us=40_000):
    out = []
    for r in records:
        sec, usec = struct.unpack_from("<ii", r, 0)
        t = sec * 1_000_000 + usec
        if out and t - out[-1][0] < window_us:
            out[-1][1].append(r)
        else:
            out.append((t, [r]))
    return [rs for _, rs in out]


def main():
    fbl, server_port, publisher_port = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
    arg = sys.argv[4] if len(sys.argv) > 4 else "5"
    flood = float(arg.split(":")[1]) if arg.startswith("flood:") else None
    gap = 0.005 if flood is not None else float(arg) / 1000.0
    tree, records = read_fbl(fbl)
    order = depth_first(tree)
    ctx = zmq.Context()
    rep = ctx.socket(zmq.REP)
    rep.setsockopt(zmq.LINGER, 0)
    rep.bind(f"tcp://127.0.0.1:{server_port}")
    pub = ctx.socket(zmq.PUB)
    pub.setsockopt(zmq.LINGER, 1000)
    pub.bind(f"tcp://127.0.0.1:{publisher_port}")
    stop = threading.Event()

    def serve():
        poller = zmq.Poller()
        poller.register(rep, zmq.POLLIN)
        while not stop.is_set():
            if poller.poll(50):
                rep.recv_multipart()
                rep.send(tree)

    server = threading.Thread(target=serve, daemon=True)
    server.start()
    print("READY", flush=True)
    sys.stdin.readline()
    status = {uid: 0 for uid in order}
    sent = 0
    if flood is not None:
        states = b"".join(struct.pack("<Hb", uid, 0) for uid in order)
        # The first record's node started and set back to IDLE, 500 times:
        # each message follows from the one before.
        sec, usec, uid = struct.unpack_from("<iiH", records[0], 0)
        start = struct.pack("<iiHbb", sec, usec, uid, 0, 1)
        back = struct.pack("<iiHbb", sec, usec, uid, 1, 0)
        msg = struct.pack("<I", len(states)) + states + struct.pack("<I", 1000) + (start + back) * 500
        until = time.time() + flood
        while time.time() < until:
            pub.send(msg)
            sent += 1000
        records = []
    for batch in batches(records):
        states = b"".join(struct.pack("<Hb", uid, status[uid]) for uid in order)
        msg = struct.pack("<I", len(states)) + states + struct.pack("<I", len(batch))
        msg += b"".join(batch)
        pub.send(msg)
        sent += len(batch)
        for r in batch:
            uid, _prev, now = struct.unpack_from("<Hbb", r, 8)
            status[uid] = now
        time.sleep(gap)
    time.sleep(1.0)
    stop.set()
    server.join()
    rep.close()
    pub.close()
    ctx.term()
    print(f"DONE {sent}", flush=True)


if __name__ == "__main__":
    main()
