#!/usr/bin/env python3
"""Writes what a Nav2 robot would record with `ros2 bag record
/behavior_tree_log`, from runs of the real BehaviorTree.CPP: each run's
.btlog (its FileLogger) becomes nav2_msgs/msg/BehaviorTreeLog messages, one
per tick (as Nav2's RosTopicLogger flushes once per tick), written by the
PyPI package `rosbags`, an implementation of rosbag2 and CDR btx's
developers did not write.

Usage: write_bag.py OUT sqlite3|mcap humble|jazzy[-cut|-nodef|-two] RUN.btlog[:RUN.json] [...]
RUN.json is tests/oracle/btcpp_run.py's: {"ticks": [[start_us, end_us], ...]}.
Runs follow each other in the bag, as goals do. With humble, the bag keeps
no message definition, as Humble's rosbag2 keeps none. With -cut, the last
run's last message never reaches the bag (some Nav2 versions do not flush
the tick that ends the run); with -nodef, a SQLite bag keeps no definition;
with -two, the last run is another robot's, on /robot2/behavior_tree_log (two
robots' namespaces recorded in one bag).

The message definitions are nav2_msgs/msg/BehaviorTreeStatusChange.msg and
BehaviorTreeLog.msg of ros-navigation/navigation2, humble (19402664a) and
jazzy (c1e7713e0): Jazzy added `uint16 uid`.
"""
import json
import sqlite3
import struct
import sys
import xml.etree.ElementTree as ET

from rosbags.rosbag2 import StoragePlugin, Writer
from rosbags.typesys import Stores, get_types_from_msg, get_typestore

CHANGE = {
    "humble": "builtin_interfaces/Time timestamp\nstring node_name\nstring previous_status\nstring current_status\n",
    "jazzy": "builtin_interfaces/Time timestamp\nstring node_name\nuint16 uid\nstring previous_status\nstring current_status\n",
}
LOG = "builtin_interfaces/Time timestamp\nBehaviorTreeStatusChange[] event_log\n"
STATUS = ["IDLE", "RUNNING", "SUCCESS", "FAILURE", "SKIPPED"]


def read_btlog(path):
    """(uid -> name, [(time_us, uid, status)]) of a FileLogger2 file."""
    b = open(path, "rb").read()
    assert b.startswith(b"BTCPP4-FileLogger2"), path
    n = struct.unpack_from("<i", b, 19)[0]
    xml = b[23:23 + n].decode()
    t0 = struct.unpack_from("<q", b, 23 + n)[0]
    names = {}
    for el in ET.fromstring(xml).iter():
        uid = el.get("_uid")
        if uid is not None:
            names[int(uid)] = el.get("name") or el.get("ID") or el.tag
    recs = []
    off = 31 + n
    while off + 9 <= len(b):
        dt = int.from_bytes(b[off:off + 6], "little")
        uid = struct.unpack_from("<H", b, off + 6)[0]
        recs.append((t0 + dt, uid, b[off + 8]))
        off += 9
    return names, recs


def main():
    out, storage, release = sys.argv[1:4]
    cut = release.endswith("-cut")
    nodef = release.endswith("-nodef")
    two = release.endswith("-two")
    release = release.removesuffix("-cut").removesuffix("-nodef").removesuffix("-two")
    # RUN.btlog alone (no tick file): a message every 40 records.
    runs = [a.split(":") if ":" in a else [a, None] for a in sys.argv[4:]]
    store = get_typestore(Stores.ROS2_HUMBLE)
    types = {}
    types.update(get_types_from_msg(CHANGE[release], "nav2_msgs/msg/BehaviorTreeStatusChange"))
    types.update(get_types_from_msg(LOG, "nav2_msgs/msg/BehaviorTreeLog"))
    store.register(types)
    Log = store.types["nav2_msgs/msg/BehaviorTreeLog"]
    Change = store.types["nav2_msgs/msg/BehaviorTreeStatusChange"]
    Time = store.types["builtin_interfaces/msg/Time"]
    plugin = StoragePlugin.MCAP if storage == "mcap" else StoragePlugin.SQLITE3
    # Runs recorded one after the other: their times already follow.
    shift = 0
    with Writer(out, version=8, storage_plugin=plugin) as w:
        conn = w.add_connection("/behavior_tree_log", "nav2_msgs/msg/BehaviorTreeLog", typestore=store)
        other = w.add_connection("/robot2/behavior_tree_log", "nav2_msgs/msg/BehaviorTreeLog", typestore=store) if two else None
        # Each node's status as the logger saw it, across goals.
        status = {}
        for btlog, meta in runs:
            names, recs = read_btlog(btlog)
            if meta is None:
                by_tick = [recs[i:i + 40] for i in range(0, len(recs), 40)]
                ticks = [(b[0][0], b[-1][0]) for b in by_tick]
            else:
                ticks = json.load(open(meta))["ticks"]
                # A record belongs to the tick whose interval holds it, or
                # the next one (a timer between ticks); one message a tick.
                by_tick = [[] for _ in ticks]
                k = 0
                for t, uid, s in recs:
                    while k < len(ticks) - 1 and t > ticks[k][1] + 200:
                        k += 1
                    by_tick[k].append((t, uid, s))
            last = [btlog, meta] == list(runs[-1])
            on = other if (two and last) else conn
            if two and last:
                status = {}
            for k, ((a, e), tick) in enumerate(zip(ticks, by_tick)):
                if not tick or (cut and last and k == max(i for i, t in enumerate(by_tick) if t)):
                    continue
                events = []
                for t, uid, s in tick:
                    t += shift
                    prev = status.get(uid, 0)
                    status[uid] = s
                    fields = dict(
                        timestamp=Time(sec=t // 1_000_000, nanosec=(t % 1_000_000) * 1000),
                        node_name=names[uid],
                        previous_status=STATUS[prev],
                        current_status=STATUS[s],
                    )
                    if release == "jazzy":
                        fields["uid"] = uid
                    events.append(Change(**fields))
                sent = e + shift + 100
                msg = Log(timestamp=Time(sec=sent // 1_000_000, nanosec=(sent % 1_000_000) * 1000), event_log=events)
                w.write(on, sent * 1000, store.serialize_cdr(msg, "nav2_msgs/msg/BehaviorTreeLog"))
    if (release == "humble" or nodef) and storage == "sqlite3":
        import glob
        for db in glob.glob(out + "/*.db3"):
            c = sqlite3.connect(db)
            c.execute("DROP TABLE IF EXISTS message_definitions")
            c.commit()
            c.close()


if __name__ == "__main__":
    main()
