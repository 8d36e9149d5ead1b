"""The floor a user writes first: a .btlog's records decoded, in Python.

    python3 benches/read_btlog.py LOG           counts the records of uid 2
    python3 benches/read_btlog.py LOG --print   prints every record as a row

It numbers no ticks and checks nothing: what it does is the least any
reader does. benches/reading.sh times btx against it.
"""
import struct
import sys

STATUS = ["IDLE", "RUNNING", "SUCCESS", "FAILURE", "SKIPPED"]
data = open(sys.argv[1], "rb").read()
n = struct.unpack("<i", data[19:23])[0]
body = memoryview(data)[31 + n:]
rows = struct.iter_unpack("<IHHB", body[: len(body) // 9 * 9])
if "--print" in sys.argv[2:]:
    out = sys.stdout
    for lo, hi, uid, st in rows:
        out.write(f"{lo | hi << 32} {uid} {STATUS[st]}\n")
else:
    print(sum(1 for r in rows if r[2] == 2))
